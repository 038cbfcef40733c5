// The passes over a shell's extracted surface: fairing, then the depth guard.
#pragma once
#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "told_pace.hpp"

namespace snvr::detail {

struct GuardElsewhere;  // guard_search.hpp

// What keep_points_deep is asked for (world units; see mesh.hpp), and where other
// processes search some of the points (null: none).
struct KeepDeep {
    double depth = 0, voxel = 0, lone = 0;
    const GuardElsewhere* elsewhere = nullptr;
};

// fair_mesh, then (when `deep`) keep_points_deep: the same results as the two public
// calls in that order, with the per-vertex lists both walk built once; `begun` told as
// each part begins (the fairing, the guard's).
DepthGuardReport fair_and_keep_deep(Mesh& mesh, const PointCloud& points, const MeshFairing& fairing,
                                    const KeepDeep* deep, const Begun& begun = nullptr);

}  // namespace snvr::detail
