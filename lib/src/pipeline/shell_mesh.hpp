// shell_mesh's passes on a level set already extracted (a tiled run's tiles make it:
// Result::surface), taken by value so that the run's copy moves in.
#pragma once
#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "told_pace.hpp"

namespace snvr::detail {

struct GuardElsewhere;  // mesh/guard_search.hpp

// The level set shell_mesh meshes where a run has not made it (Result::surface_made): its
// phase field's, by dual marching cubes.
Mesh level_set_of(const Result& result);
// `elsewhere`: other processes search some of the points for the depth guard (null: none);
// `begun`: told as each of its parts begins.
Mesh shell_mesh_of(Mesh surface, const Result& result, const PointCloud& points, DepthGuardReport* guard,
                   const MeshFairing& fairing, const GuardElsewhere* elsewhere = nullptr,
                   const Begun& begun = nullptr);

}  // namespace snvr::detail
