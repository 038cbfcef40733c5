// Where the tiles of a tiled run (Parameters::tile_cells) run. Without a scheduler they
// all run in this process, one after another. A scheduler spreads them over processes
// (snvr-cl's MPI one, cli/processes_mpi.cpp): the points' tree is filed by all (each
// reading its part of the input where it can, else given it: read_input, serve_input),
// the root (rank 0) holding the whole tree; it makes the plan and the global decisions,
// and gives each other process the plan, which process runs which tile, and the points
// within reach of its own tiles (reconstruct_tiles_of); each runs the tiles it owns (balanced by the points
// near them) and sends the results to the root, which puts the cores together and goes on
// to mesh (or, Parameters::whole_field false, each sends the bricks near its core's faces
// and keeps its part of the surface; then each welds and fairs a slab of planes of the
// surface from the parts and seams there, which the root puts together:
// lib/src/solver/shared_slabs.hpp); on the other processes the call returns once their
// tiles and slab are sent, without a phase field or a mesh (Result::tiles.worker). Before the plan goes out, a sparse scan's points added on the
// surface are shared too (UpsampleShare). After the tiles the depth guard's first search
// is shared by the ranges of the points each kept (lib/src/pipeline/shared_guard.hpp, in
// send_bytes' messages), and make_shell's check is then shared too: each other process
// measures the walls and points' depths the root gives it (CheckShare,
// measure_check_share): the depths of its own range of the points filed by all, which it
// keeps from the filing on (points_kept), or else of the points the root sends it.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "snvr/field.hpp"
#include "snvr/geometry.hpp"

namespace snvr {
namespace detail {
struct KeptRange;  // lib/src/solver/shared_filing.hpp
}

// A share of the shell's check that another process takes (lib/src/check/check_share.cpp):
// the triangles near what it measures (in the shell's order), the vertices among them
// whose walls it measures, and the points whose depths it measures: where it kept its
// range of the points filed by all (lib/src/solver/shared_filing.hpp), groups of its
// range's own points (`range_groups`); and points given (`points`: some of the rest,
// dealt by tile). Never the groups the root samples for the percentile. The share holds every
// triangle within `reach` of those vertices and points: a wall met within it, or a point's
// nearest triangle within it, is the whole shell's; the rest come back for the root.
struct CheckShare {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> measured;  // of `vertices`
    double epsilon = 0;                   // the least distance a hit counts at (the shell's)
    double reach = 0;
    Vec3 origin{0, 0, 0};       // the points (given or kept): float coordinates about it
    std::vector<float> points;  // x y z in turn
    // The points given, in the root's groups: each a count of consecutive points (all of
    // them in all); empty: grouped here as their own tree's leaves fall.
    std::vector<std::uint32_t> point_groups;
    double voxel = 0;           // the run's (the points are measured in groups of its size)
    // The Morton frame (its low corner, then cells a unit) of the root's tree, whose order
    // the points keep: filed in it they need no sorting. A scale of 0: none.
    std::array<double, 4> points_frame{0, 0, 0, 0};
    // The kept range's groups, [begin, end) of its order; its size as the root has it; and
    // every scale factor the root's points took since they were filed (the range takes
    // those it has not).
    std::vector<std::array<std::uint32_t, 2>> range_groups;
    std::uint64_t range_size = 0;
    std::vector<double> range_scaled;
};

// What a share measured: each measured vertex's wall (CheckShare::measured's order; NaN
// beyond the reach), and its points' figures, but for the points it could not decide
// (places in the kept range, then range_size + indices into CheckShare::points).
struct CheckShareFigures {
    std::vector<double> walls;
    std::uint64_t points_inside = 0;
    double depth_min = 0;  // the least depth of a point inside (infinity: none)
    std::vector<std::uint32_t> unresolved;
};

// The points another process adds on the surface for the root before the tiles (a sparse
// scan's, surface_upsampling.hpp): those of the run [begin, end) of the whole cloud's
// order, the cloud given whole (float coordinates about `origin`, x y z in turn, in its
// order: filed in `points_frame`, it is the root's again). spacing 0: none to add in this run.
struct UpsampleShare {
    Vec3 origin{0, 0, 0};
    std::vector<float> points;
    double spacing = 0;
    std::uint64_t begin = 0, end = 0;
    // The root's tree's Morton frame (as CheckShare's): filed in it, the points keep the
    // root's order, which [begin, end) counts in.
    std::array<double, 4> points_frame{0, 0, 0, 0};
};

// One tile's run, as the root needs it.
struct TileResult {
    std::size_t tile = 0;
    Field field;                  // the tile's phase field, on the tile's own grid (without the
                                  // whole field: only the bricks near its core's faces)
    std::vector<double> figures;  // its steps and facts, flattened (tiled_reconstruct.cpp)
};

class TileScheduler {
public:
    virtual ~TileScheduler() = default;
    // At another process: its range of the points filed by all, kept by serve_input for
    // serve_shell's check (null: none).
    std::shared_ptr<detail::KeptRange> points_kept;
    virtual int processes() const = 0;
    virtual int rank() const = 0;  // 0: the root
    // A worker's result to the root (sent on while the worker goes on: it keeps the
    // result until sent() has waited for the root to take it).
    virtual void send(TileResult result) = 0;
    virtual void sent() = 0;
    // At the root: whether a result has come in, and the next that has (waiting for one).
    virtual bool waiting() = 0;
    virtual TileResult receive() = 0;
    // The elementwise largest of every process's `mine`, on every process.
    virtual std::vector<int> most(const std::vector<int>& mine) = 0;
    // First of all, at the root: each other process's share of the points added on the
    // surface (given to every one, spacing 0 where none are added), then what it added
    // (world units, x y z in turn); at another process, its share and what it added back.
    virtual void give_upsampling(int process, const UpsampleShare& share) = 0;
    virtual std::vector<double> take_upsampled(int process) = 0;
    virtual UpsampleShare upsampling() = 0;
    virtual void send_upsampled(const std::vector<double>& xyz) = 0;
    // The root's `plan` figures and tile `owners` to every process (the others' are
    // replaced).
    virtual void share(std::vector<double>& plan, std::vector<int>& owners) = 0;
    // At the root: a process's points, float coordinates about `origin`, x y z in turn
    // (`floats` of them).
    virtual void give_points(int process, const Vec3& origin, const float* xyz, std::size_t floats) = 0;
    // At another process: its points from the root, put where room(floats) says (the caller's
    // own array, which a run under a budget may keep in a file).
    virtual void take_points(Vec3& origin, const std::function<float*(std::size_t floats)>& room) = 0;
    // Plain bytes from this process to another, received in the order sent (the points'
    // tree filed by all processes, lib/src/solver/shared_filing.hpp, and the depth guard's
    // search by their ranges, lib/src/pipeline/shared_guard.hpp): sent before
    // send_bytes returns; received into room(size), which gives where they go.
    virtual void send_bytes(int process, const void* bytes, std::size_t size) = 0;
    virtual void receive_bytes(int process, const std::function<void*(std::size_t size)>& room) = 0;
    // Each of `values` summed over every process, or the least of them, on every process.
    virtual void sum(std::vector<std::uint64_t>& values) = 0;
    virtual void least(std::vector<double>& values) = 0;
    // The shell's check shared, once the tiles are done: at the root, each other process's
    // share (given to every one of them, empty when there is none: first its points, then
    // the rest, share.points unused, so that the root never holds both) and later what it
    // measured; at another process, its share, whole, and what it measured back.
    virtual void give_check_points(int process, const Vec3& origin, const float* xyz, std::size_t floats) = 0;
    virtual void give_check(int process, const CheckShare& share) = 0;
    virtual CheckShareFigures take_check(int process) = 0;
    virtual CheckShare check_share() = 0;
    virtual void send_check(const CheckShareFigures& figures) = 0;
};

}  // namespace snvr
