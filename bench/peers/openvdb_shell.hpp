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

// Narrow-band half-width of the level set, in voxels (OpenVDB's own default; the
// filter's 5th-order WENO stencils read 3 voxels to each side).
constexpr double kPeerHalfWidth = 3.0;
// ParticlesToLevelSet drops balls smaller than this many voxels (its Nyquist limit).
constexpr double kPeerMinRadiusVoxels = 1.5;

// `voxel` and `offset` in world units. Throws snvr::ParameterError when a length is
// not positive, when offset / voxel is below kPeerMinRadiusVoxels (OpenVDB would
// silently skip every ball and return an empty mesh) or when steps < 0.
PeerShell openvdb_shell(const PointSet& points, double voxel, double offset, int curvature_steps = 4);

}  // namespace snvr::peers
