// The mesh formats' writers, each streaming one mesh into an AtomicFile.
#pragma once
#include "io/atomic_file.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

void write_3mf(const Mesh& mesh, AtomicFile& out);  // write_3mf.cpp: lib3mf, millimetres

}  // namespace snvr::detail
