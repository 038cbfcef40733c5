// The library's verdict on a shell, as sentences a user can act on.
#include <cstdio>
#include <string>
#include <vector>

#include "snvr/quality.hpp"

namespace snvr {

namespace {

template <class... Args>
std::string sentence(const char* format, Args... args) {
    char text[320];
    std::snprintf(text, sizeof text, format, args...);
    return text;
}

}  // namespace

std::vector<std::string> shell_warnings(const MeshQuality& q, std::size_t points, std::size_t clusters,
                                        std::size_t dropped_pieces) {
    const MeshReport& m = q.report;
    std::vector<std::string> out;
    if (m.solids > clusters)
        out.push_back(sentence("the shell fell apart into %zu solid pieces, but the points form %zu cluster%s at twice "
                               "the offset: raise the offset (or lower the resolution) to close the gaps",
                               m.solids, clusters, clusters == 1 ? "" : "s"));
    if (!m.closed()) out.push_back(sentence("the mesh is not closed: %zu boundary edges", m.boundary_edges));
    if (!m.manifold())
        out.push_back(sentence("the mesh is not manifold: %zu non-manifold edges, %zu non-manifold vertices, "
                               "%zu degenerate triangles",
                               m.nonmanifold_edges, m.nonmanifold_vertices, m.degenerate_triangles));
    if (m.zero_area_triangles)
        out.push_back(sentence("%zu triangles have zero area (slicers report them as errors)", m.zero_area_triangles));
    if (!m.oriented())
        out.push_back(sentence("the mesh is not consistently oriented: %zu misoriented edges, volume %.6g",
                               m.misoriented_edges, m.volume));
    if (q.points_inside < points)
        out.push_back(dropped_pieces
                          ? sentence("the shell encloses %zu of %zu points (%zu piece%s dropped on request)",
                                     q.points_inside, points, dropped_pieces, dropped_pieces == 1 ? "" : "s")
                          : sentence("the shell encloses %zu of %zu points; a larger offset or a finer grid may help",
                                     q.points_inside, points));
    return out;
}

}  // namespace snvr
