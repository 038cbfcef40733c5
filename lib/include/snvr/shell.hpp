// The printable shell as one call: what `snvr-cl reconstruct` does between reading the
// points and writing its files (outliers, reconstruction, mesh, fairing, depth guard,
// debris pieces, the check and its warnings), for any program that links libsnvr.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/parameters.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"

namespace snvr {

class MeshSink;  // snvr/mesh_io.hpp

// Where the shell is made: about the points as given, about their round centre (far
// coordinates), or (Auto, snvr-cl's default) about the centre only where written_as is a
// print format (STL, 3MF) whose float32 would otherwise move the shell by more than 1% of
// a voxel (decided on the points as given, at the smallest voxel the run can have).
enum class ShellOrigin { Auto, Keep, Centre };

// The points a reconstruction starts from: a point file as read_point_cloud reads it, or
// a mesh (.stl; .ply, .obj or .off with faces; any of them gzipped) with its triangles
// sampled at half the voxel the run will have (sample_triangles), so that its faces,
// not only its corners, are thickened.
struct InputPoints {
    PointCloud points;
    std::size_t triangles = 0;  // the mesh's, when the input was one
    double spacing = 0;         // the sampling's
};
// `others`: the processes of a run spread over them (ShellSettings::tiles_on), each in
// serve_input meanwhile: they file the points' tree with this one (the same tree, sooner).
InputPoints read_input(const std::string& path, const Parameters& params, TileScheduler* others = nullptr);

// The shell's surface: the zero level set of result.phi, meshed the way snvr-cl does
// (closed, manifold, outward), faired (fair_mesh), and, when the run kept a tube, lifted where the mesh dips
// nearer to a point than the tube's inner wall (keep_points_deep; every point when the
// offset is at least the sampling gap, else the points with a neighbour within the
// offset). `points` are the reconstruction's input. One place for the default mesher.
Mesh shell_mesh(const Result& result, const PointCloud& points, DepthGuardReport* guard = nullptr,
                const MeshFairing& fairing = {});
Mesh shell_mesh(const Result& result, const PointSet& points, DepthGuardReport* guard = nullptr,
                const MeshFairing& fairing = {});  // makes a PointCloud

// The outlier rules (OutlierSettings, point_cloud.hpp) measured by the run `params`
// plans for the points kept so far.
OutlierSplit split_outliers(const PointSet& points, const Parameters& params, const OutlierSettings& settings = {});
// The same rules on a cloud, in place: the outliers leave `points` and are returned.
DroppedOutliers drop_outliers(PointCloud& points, const Parameters& params, const OutlierSettings& settings = {});

// Millimetres in one of the length units the points may be given in (mm, cm, m, in);
// 0 for another name.
double millimetres_per_unit(const std::string& unit);

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
    // Called once with the finished mesh (Shell::mesh as returned) during the check, which
    // does not change it: a caller writes it there, over several processes while the
    // others finish their share of the check (the first process takes that much less of
    // it, reckoning the writing of written_as's format). What it throws, make_shell throws.
    std::function<void(const Mesh&)> mesh_ready;
    // Or the finished mesh handed to a sink in parts (snvr/mesh_io.hpp: OutputFiles::
    // mesh_sink writes a file so), once: then Shell::mesh comes back empty. Over several
    // processes the slabs that made it are handed on in turn after the check, so that no
    // process holds it whole, where nothing needs it so (a piece filter, the surface's
    // figures, keep_field, or the depth guard on a dense scan's whole surface:
    // Result::tiles.slabs_kept says which); else it is handed on whole, as mesh_ready.
    std::shared_ptr<MeshSink> mesh_sink;
    // Where a tiled run's tiles run (tiles.hpp); none: all in this process.
    std::shared_ptr<TileScheduler> tiles_on;
    // The points' length unit and a factor on it (a print at 1:100 is scale 0.01): the
    // points and every length above are taken times scale in that unit, and the shell is
    // made and returned in millimetres, the unit slicers assume.
    std::string units = "mm";
    double scale = 1;
    static constexpr double min_scale = 1e-6, max_scale = 1e6;  // beyond any printer; further, float range goes
    static constexpr const char* scale_range = "a factor from 1e-6 to 1e6";  // as messages say it
    double to_millimetres() const { return scale * millimetres_per_unit(units); }
    void validate() const;       // throws ParameterError naming the bad value (every part's rules)
};

struct ShellSeconds {
    double outliers = 0, reconstruct = 0, mesh = 0, check = 0, total = 0;  // reconstruct: run.seconds has its stages
    double mesh_ready = 0;  // in ShellSettings::mesh_ready or mesh_sink (within total, not in check)
};

struct Shell {
    Mesh mesh;                  // shifted by -shift; as written_as holds it (empty: given to mesh_sink)
    Result run;                 // the reconstruction; phi only when keep_field
    DroppedOutliers outliers;   // the points dropped, where they were given
    Vec3 shift{0, 0, 0};        // subtracted from the kept points before the run (origin)
    bool shift_by_default = false;  // shifted by ShellOrigin::Auto's rule, not on request
    std::size_t points = 0;     // the points the shell was made around
    std::string units = "mm";   // the points' unit as given, and
    double to_millimetres = 1;  // what their lengths were multiplied by (everything here is in mm)
    Vec3 size{0, 0, 0};         // the mesh's extent along x, y and z
    DepthGuardReport guard;
    PieceReport pieces;
    MeshQuality quality;        // the check: closed, pieces, points inside and their depth, walls
    std::size_t clusters = 0;   // count_point_clusters(kept points, 2 l)
    std::vector<std::string> warnings;  // the run's, the depth guard's, the check's, the size's
    ShellSeconds seconds;
};

// Progress of make_shell (as reconstruct's, Progress in reconstruct.hpp): the stages
// "outliers", "domain", "distance", "init", "step", "mesh" and "check" ("outliers" and
// "mesh" and "check" as they begin, then with a message: how far the stray rule's tests
// and the check's walls and depths have come, the mesh stage's parts as each begins;
// with Progress::outcome, what a stage did: the outliers dropped, the vertices the depth
// guard lifted, the pieces dropped). Returning false cancels: Cancelled.

// Throws InputError, ParameterError, ResourceError or IoError naming the problem;
// Error when the shell comes out empty (every piece below pieces.min_volume, or none at
// all); Cancelled when the progress callback asks.
Shell make_shell(PointCloud points, const ShellSettings& settings, const ProgressCallback& progress = {});
Shell make_shell(const PointSet& points, const ShellSettings& settings, const ProgressCallback& progress = {});

// Another process's part of a make_shell spread over processes (tiles.hpp): its tiles
// (reconstruct_tiles_of), its range's part of the depth guard's search where the root
// asks, then its share of the check (measure_check_share), sent to the root; under the run's budget, its points' arrays beyond it in files as make_shell's.
void serve_shell(const Parameters& params, TileScheduler& tiles_on);
// Another process's part of the root's read_input(path, params, others): its share of
// reading (where the file can be read in parts) and filing the points (nothing where the
// root reads a mesh or few points); then serve_shell.
void serve_input(const std::string& path, const Parameters& params, TileScheduler& tiles_on);

}  // namespace snvr
