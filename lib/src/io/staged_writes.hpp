// The writers' first half: the whole file written to its temporary, not yet renamed
// onto the target (that is AtomicFile::commit()), so that several outputs can
// appear together (OutputFiles) or each alone (write_mesh, write_field, write_points).
#pragma once
#include <memory>
#include <string>

#include "io/atomic_file.hpp"
#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

std::unique_ptr<AtomicFile> stage_mesh(const Mesh& mesh, const std::string& path);
std::unique_ptr<AtomicFile> stage_field(const Field& field, const Domain& domain, const std::string& path);
std::unique_ptr<AtomicFile> stage_points(const PointSet& points, const std::string& path, const std::string& comment);

}  // namespace snvr::detail
