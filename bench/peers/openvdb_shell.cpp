// OpenVDB's particles -> level set -> filter -> mesh pipeline, timed per stage.
#include "openvdb_shell.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/stopwatch.hpp"

namespace snvr::peers {
namespace {

// ParticlesToLevelSet reads particles through this interface; no copy of the points.
class ParticleView {
public:
    using PosType = openvdb::Vec3R;
    explicit ParticleView(const PointSet& points) : points_(points) {}
    size_t size() const { return points_.size(); }
    void getPos(size_t n, openvdb::Vec3R& xyz) const { xyz = openvdb::Vec3R(points_[n][0], points_[n][1], points_[n][2]); }

private:
    const PointSet& points_;
};

double signed_volume(const Mesh& mesh) {
    double six_v = 0;
    for (const auto& t : mesh.triangles) {
        const Vec3& a = mesh.vertices[t[0]];
        const Vec3& b = mesh.vertices[t[1]];
        const Vec3& c = mesh.vertices[t[2]];
        six_v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return six_v / 6.0;
}

Mesh to_mesh(const std::vector<openvdb::Vec3s>& points, const std::vector<openvdb::Vec3I>& triangles,
             const std::vector<openvdb::Vec4I>& quads) {
    Mesh mesh;
    mesh.vertices.reserve(points.size());
    for (const auto& p : points) mesh.vertices.push_back({double(p[0]), double(p[1]), double(p[2])});
    mesh.triangles.reserve(triangles.size() + 2 * quads.size());
    for (const auto& t : triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
    // The split every user writes: the fixed diagonal 0-2 (the quads are planar only
    // approximately, so the choice shows in dihedral angles; keep it the common one).
    for (const auto& q : quads) {
        mesh.triangles.push_back({q[0], q[1], q[2]});
        mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    // Which way volumeToMesh winds its polygons depends on the sign convention of the
    // grid; decide from the result, so that normals point out of the solid.
    if (signed_volume(mesh) < 0)
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    return mesh;
}

}  // namespace

PeerShell openvdb_shell(const PointSet& points, double voxel, double offset, int curvature_steps) {
    if (!(voxel > 0) || !(offset > 0) || !std::isfinite(voxel) || !std::isfinite(offset))
        throw ParameterError("openvdb_shell: voxel and offset must be positive and finite");
    if (curvature_steps < 0) throw ParameterError("openvdb_shell: curvature steps must be >= 0");
    PeerShell out;
    out.radius_voxels = offset / voxel;
    if (out.radius_voxels < kPeerMinRadiusVoxels)
        throw ParameterError("openvdb_shell: offset / voxel = " + std::to_string(out.radius_voxels) +
                             " is below ParticlesToLevelSet's smallest radius of " +
                             std::to_string(kPeerMinRadiusVoxels) + " voxels (it would drop every ball)");
    openvdb::initialize();
    Stopwatch total, stage;

    auto grid = openvdb::createLevelSet<openvdb::FloatGrid>(voxel, kPeerHalfWidth);
    {
        openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
        // Its default largest radius (100 voxels) would drop the balls of a very coarse run.
        raster.setRmax(std::max(raster.getRmax(), 2 * out.radius_voxels));
        raster.rasterizeSpheres(ParticleView(points), offset);  // radius in world units
        raster.finalize();
        if (raster.ignoredParticles())
            throw Error("openvdb_shell: ParticlesToLevelSet ignored " +
                        std::to_string(raster.getMinCount() + raster.getMaxCount()) + " particles");
    }
    out.seconds_level_set = stage.lap();

    {
        openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
        filter.setSpatialScheme(openvdb::math::FIRST_BIAS);  // see kPeerHalfWidth
        filter.setTemporalScheme(openvdb::math::TVD_RK1);
        filter.setNormCount(1);  // one renormalisation sweep per step (default: the half width)
        for (int s = 0; s < curvature_steps; ++s) filter.meanCurvature();
    }
    out.seconds_filter = stage.lap();

    std::vector<openvdb::Vec3s> vdb_points;
    std::vector<openvdb::Vec3I> vdb_triangles;
    std::vector<openvdb::Vec4I> vdb_quads;
    openvdb::tools::volumeToMesh(*grid, vdb_points, vdb_triangles, vdb_quads, /*isovalue=*/0.0,
                                 /*adaptivity=*/0.0);
    out.mesh = to_mesh(vdb_points, vdb_triangles, vdb_quads);
    out.seconds_mesh = stage.lap();
    out.seconds_total = total.lap();
    return out;
}

}  // namespace snvr::peers
