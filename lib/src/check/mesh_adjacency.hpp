// The adjacency check_mesh builds (mesh_check.cpp), shared with measure_quality so the
// figures reuse it rather than build it again.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"

namespace snvr::detail {

void vertex_fans(const Mesh& mesh, std::vector<std::size_t>& start, std::vector<std::uint32_t>& tri);
void lower_edges(const Mesh& mesh, std::vector<std::size_t>& start, std::vector<std::uint64_t>& items);
MeshReport check_mesh_unchecked(const Mesh& mesh, const std::vector<std::size_t>& fan_start,
                                const std::vector<std::uint32_t>& fan_tri, const std::vector<std::size_t>& edge_start,
                                const std::vector<std::uint64_t>& edge_items, std::vector<std::uint32_t>* piece);

}  // namespace snvr::detail
