// The triangles' vertex indices checked against the mesh's vertices, for every pass
// that takes a mesh from outside.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>

#include "snvr/error.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

// Throws InputError, starting with `who`, naming the first triangle that uses a vertex
// the mesh does not have.
inline void check_triangle_indices(const Mesh& mesh, const char* who) {
    const std::size_t nv = mesh.vertices.size();
    // The largest index first (a loop without branches): there is rarely anything to report.
    std::uint32_t top = 0;
    for (const auto& t : mesh.triangles) top = std::max(top, std::max(t[0], std::max(t[1], t[2])));
    if (mesh.triangles.empty() || top < nv) return;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t])
            if (v >= nv)
                throw InputError(std::string(who) + ": triangle " + std::to_string(t) + " uses vertex " +
                                 std::to_string(v) + " of " + std::to_string(nv));
}

}  // namespace snvr::detail
