// make_shell's check over the processes of a tiled run (tiles.hpp): the walls, the most
// of the check's work, measured by each process for the vertices in its tiles' cores (the
// first's own tiles dealt to all in turn) from the triangles near them, while the first
// does the rest of the check.
#pragma once
#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// measure_quality (surface) or measure_shell of `mesh`, the same figures, its walls shared
// with the other processes of `on` (each is given its share, empty where it has none).
MeshQuality check_sharing_walls(const Mesh& mesh, const PointCloud& points, const Result& run, bool surface,
                                TileScheduler& on);

}  // namespace snvr::detail
