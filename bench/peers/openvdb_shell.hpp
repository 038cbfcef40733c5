// The pipeline users compare libsnvr with, built on OpenVDB: a union of balls of
// radius `offset` around the points (ParticlesToLevelSet), a few mean-curvature
// flow steps (LevelSetFilter), and the zero isosurface (volumeToMesh).
#pragma once
#include "snvr/geometry.hpp"

namespace snvr::peers {

struct PeerShell {
    Mesh mesh;  // welded, outward oriented (quads split into two triangles each)
    double seconds_level_set = 0, seconds_filter = 0, seconds_mesh = 0, seconds_total = 0;
    double radius_voxels = 0;  // offset / voxel, the radius ParticlesToLevelSet rasterizes
};

// Narrow-band half-width of the level set, in voxels. The filter runs first-order
// upwind renormalisation (FIRST_BIAS, TVD_RK1), whose stencils read one voxel to each
// side, so two voxels suffice, with one renormalisation sweep per step: what a user
// tuning OpenVDB for speed would choose.
// Measured on the bunny at 256 (issue 9): OpenVDB's defaults (half width 3, WENO5,
// the filter's own time scheme) take 3.7-5.1 s in the filter for 3.94 / 1.15 deg;
// these settings take 0.73-0.89 s for 3.86 / 1.15 deg, the same offset error and depth.
constexpr double kPeerHalfWidth = 2.0;
// ParticlesToLevelSet drops balls smaller than this many voxels (its Nyquist limit).
constexpr double kPeerMinRadiusVoxels = 1.5;

// `voxel` and `offset` in world units. Throws snvr::ParameterError when a length is
// not positive, when offset / voxel is below kPeerMinRadiusVoxels (OpenVDB would
// silently skip every ball and return an empty mesh) or when steps < 0.
PeerShell openvdb_shell(const PointSet& points, double voxel, double offset, int curvature_steps = 4);

}  // namespace snvr::peers
