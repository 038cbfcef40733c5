// The printable shell as one call: what `snvr-cl reconstruct` does between reading the
// points and writing its files (outliers, reconstruction, mesh, fairing, depth guard,
// debris pieces, the check and its warnings), for any program that links libsnvr.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

// Where the shell is made: about the points as given, about their round centre (far
// coordinates), or (Auto, snvr-cl's default) about the centre only where written_as is a
// print format (STL, 3MF) whose float32 would otherwise move the shell by more than 1% of
// a voxel (decided on the points as given, at the smallest voxel the run can have).
enum class ShellOrigin { Auto, Keep, Centre };

struct ShellSettings {
    Parameters params;           // lengths in the points' units
    bool drop_outliers = true;   // the outlier rules (false: every point is used)
    OutlierSettings outliers;
    ShellOrigin origin = ShellOrigin::Auto;  // Centre: the kept points shifted by round_centre before the run
    MeshFairing fairing;
    PieceFilter pieces;          // min_volume in the points' units cubed
    bool measure = false;        // the check measures the surface too (measure_quality)
    // A file name (or just its extension) the mesh is meant for: the mesh comes back as
    // that format holds it (float32 for STL, PLY and 3MF) and is checked so; IoError
    // when the format cannot hold it faithfully. Empty: doubles, as meshed.
    std::string written_as;
    bool keep_field = false;     // keep run.phi (else freed before the check)
};

struct ShellSeconds {
    double outliers = 0, reconstruct = 0, mesh = 0, check = 0, total = 0;  // reconstruct: run.seconds has its stages
};

struct Shell {
    Mesh mesh;                  // shifted by -shift; as written_as holds it
    Result run;                 // the reconstruction; phi only when keep_field
    DroppedOutliers outliers;   // the points dropped, where they were given
    Vec3 shift{0, 0, 0};        // subtracted from the kept points before the run (origin)
    bool shift_by_default = false;  // shifted by ShellOrigin::Auto's rule, not on request
    std::size_t points = 0;     // the points the shell was made around
    DepthGuardReport guard;
    PieceReport pieces;
    MeshQuality quality;        // the check: closed, pieces, points inside and their depth, walls
    std::size_t clusters = 0;   // count_point_clusters(kept points, 2 l)
    std::vector<std::string> warnings;  // the run's, the depth guard's, the check's
    ShellSeconds seconds;
};

// Progress of make_shell: the stages "outliers", "domain", "distance", "init", "step",
// "mesh" and "check" as they begin (steps as they end; "outliers" again when points were
// dropped, saying how many). Returning false cancels: the call stops there, frees what
// it holds and throws Cancelled.
using ShellProgress = std::function<bool(const Progress&)>;

// Throws InputError, ParameterError, ResourceError or IoError naming the problem;
// Error when the shell comes out empty (every piece below pieces.min_volume, or none at
// all); Cancelled when the progress callback asks.
Shell make_shell(PointCloud points, const ShellSettings& settings, const ShellProgress& progress = {});
Shell make_shell(const PointSet& points, const ShellSettings& settings, const ShellProgress& progress = {});

}  // namespace snvr
