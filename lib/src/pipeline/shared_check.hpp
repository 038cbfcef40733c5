// make_shell's check over the processes of a tiled run (tiles.hpp): the walls and the
// points' depths, the most of the check's work, measured by each process for the vertices
// and points in its tiles' cores (the first's own tiles dealt to whoever has the least
// work) from the triangles near them, while the first does the rest of the check.
#pragma once
#include <functional>

#include "check/walls.hpp"
#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// measure_quality (surface) or measure_shell of `mesh`, the same figures, its walls (and
// without the surface's figures, its points' depths) shared with the other processes of
// `on` (each is given its share, empty where it has none); what the others measured goes
// to `facts` (TileFacts::check_walls and on). `meanwhile` runs here once this process has
// measured its own part, before it takes the others' figures: about meanwhile_seconds,
// which it measures less for.
MeshQuality check_sharing(const Mesh& mesh, const PointCloud& points, const Result& run, bool surface,
                          TileScheduler& on, TileFacts& facts, const std::function<void()>& meanwhile = {},
                          double meanwhile_seconds = 0, const Told& told = nullptr);

}  // namespace snvr::detail
