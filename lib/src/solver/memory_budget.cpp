// fit_memory (memory_budget.hpp).
#include "solver/memory_budget.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "geometry/point_tree.hpp"
#include "process_limits.hpp"
#include "snvr/error.hpp"
#include "solver/brick_grid.hpp"
#include "solver/solver_memory.hpp"
#include "solver/tile_needs.hpp"
#include "solver/tile_plan.hpp"

namespace snvr {

namespace {

// The model's constants (memory_budget.hpp), measured per near brick with snvr-cl's
// resident memory sampled through each stage (bunny at 512 and 1024 cells, dragon,
// igea at 512, cactus and a random sphere of 1,500 points at 256, the 24.6 M-point sphere
// at 256, the 200 M-point city block at 1024 and 2048): the solver held 2.6-4.2 x 512 r a
// near brick (most near bricks are in the band); the meshes had 45-87 triangles a near
// brick; the mesh stage and the check peaked 49-87 bytes a triangle above where they
// began (the field then held beside them); the check's points a few bytes each at most
// (2026-11-29, anonymous memory sampled through the check: the 98.5 M-point sphere at
// 256, 1.07 M triangles, 256 MB, 0.6 a point beyond the triangles' model; the 50 M-point
// city block at 1024, 8.8 M triangles, 1.48 GB, under the triangles' model alone). Where
// the tiles make the surface no field is held then, and the mesh stage and the check,
// measured from a clean start, peaked at 108-110 bytes a triangle (the bunny and igea at
// 512, 3.3-3.4 M triangles): the check's, once the field is freed. Each is taken with a
// margin. (The depth search's triangle frames, 72 bytes a triangle where points cover
// them all, came on top until they were cached a few MB a thread: the 12.5 M-point city
// block at 1024, 1.80 GB peak where 1.24.)
constexpr double kSolverCopies = 5;
constexpr std::size_t kTrianglesPerBrick = 90;
constexpr std::size_t kMeshBytesPerTriangle = 90;    // beside the field (extraction, fairing, guard)
constexpr std::size_t kCheckBytesPerTriangle = 110;  // alone, the field freed (the check)
constexpr std::size_t kCheckBytesPerPoint = 2;
// A tile's part of the surface (tile_surface.hpp), a triangle's share: its corners, keys
// and the half vertex each triangle has (24 + 8 + 1 bytes), 33 bytes; with a margin.
constexpr std::size_t kSurfaceBytesPerTriangle = 40;

// An OpenCL runtime's own memory once loaded (PoCL on this machine: 80 MiB resident).
constexpr std::size_t kDeviceRuntimeBytes = std::size_t(96) << 20;

// The grid's bricks within `reach` of a point: a bit each, x fastest.
class NearBricks {
public:
    NearBricks(const detail::PointTree& tree, const Domain& d, double reach)
        : n_{(d.nx + kBrick - 1) / kBrick, (d.ny + kBrick - 1) / kBrick, (d.nz + kBrick - 1) / kBrick},
          bits_((std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]) + 63) / 64, 0) {
        // Nodes no wider than half a brick stand for their points (a dense scan's leaves are
        // thousands to a brick): their boxes reach hardly any brick more.
        const double brick = d.h * kBrick;
        std::vector<const detail::PointTree::Node*> leaves;
        tree.for_each_leaf(
            [&](const detail::PointTree::Node& n) {
                const Vec3 lo = tree.lo(n), hi = tree.hi(n);
                if (std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) > brick / 2 || n.leaf()) return true;
                leaves.push_back(&n);
                return false;
            },
            [&](const detail::PointTree::Node& leaf) { leaves.push_back(&leaf); });
        const std::ptrdiff_t count = std::ptrdiff_t(leaves.size());
#pragma omp parallel for schedule(dynamic, 4096)
        for (std::ptrdiff_t l = 0; l < count; ++l) {
            const Vec3 lo = tree.lo(*leaves[std::size_t(l)]), hi = tree.hi(*leaves[std::size_t(l)]);
            int first[3], last[3];
            for (int a = 0; a < 3; ++a) {
                first[a] = std::max(0, int(std::floor((lo[a] - reach - d.origin[std::size_t(a)]) / brick)));
                last[a] = std::min(n_[a] - 1, int(std::floor((hi[a] + reach - d.origin[std::size_t(a)]) / brick)));
            }
            for (int k = first[2]; k <= last[2]; ++k)
                for (int j = first[1]; j <= last[1]; ++j)
                    for (int i = first[0]; i <= last[0]; ++i) {
                        const std::size_t b = index(i, j, k);
                        const std::uint64_t bit = std::uint64_t(1) << (b % 64);
                        if (bits_[b / 64] & bit) continue;
#pragma omp atomic
                        bits_[b / 64] |= bit;
                    }
        }
    }

    std::size_t count() const {
        std::size_t c = 0;
        for (std::uint64_t w : bits_) c += std::size_t(__builtin_popcountll(w));
        return c;
    }

    // The most near bricks in one tile's box (halo included).
    std::size_t most_in_a_tile(const std::vector<Tile>& tiles, const Domain& d, int core_cells, int halo_cells) const {
        std::vector<std::size_t> in(tiles.size(), 0);
        for (std::size_t w = 0; w < bits_.size(); ++w)
            for (std::uint64_t bits = bits_[w]; bits; bits &= bits - 1) {
                const std::size_t b = w * 64 + std::size_t(__builtin_ctzll(bits));
                const std::array<int, 3> lo = {int(b % std::size_t(n_[0])) * kBrick,
                                               int(b / std::size_t(n_[0]) % std::size_t(n_[1])) * kBrick,
                                               int(b / (std::size_t(n_[0]) * std::size_t(n_[1]))) * kBrick};
                const std::array<int, 3> hi = {lo[0] + kBrick, lo[1] + kBrick, lo[2] + kBrick};
                for_tiles_meeting(tiles, d, core_cells, halo_cells, lo, hi, [&](std::size_t t) { ++in[t]; });
            }
        return in.empty() ? 0 : *std::max_element(in.begin(), in.end());
    }

private:
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(n_[0]) * (std::size_t(j) + std::size_t(n_[1]) * std::size_t(k));
    }
    int n_[3];
    std::vector<std::uint64_t> bits_;
};

std::size_t solver_bytes(std::size_t near_bricks, std::size_t real) {
    return std::size_t(kSolverCopies * double(near_bricks * kBrickCells * real));
}

std::string gib(std::size_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g GiB", double(bytes) / double(std::size_t(1) << 30));
    return text;
}

// The stages after the decision: the largest, and its name.
struct Peak {
    std::size_t bytes = 0;
    std::string what;
};
// The mesh stage: the field beside the mesh (field_held), then the check alone (f.mesh,
// counted at the check's bytes a triangle).
std::size_t mesh_stage(const MemoryFacts& f, std::size_t field_held) {
    const std::size_t triangles = f.near_bricks * kTrianglesPerBrick;
    const std::size_t beside =
        field_held + f.mesh - std::min(f.mesh, triangles * (kCheckBytesPerTriangle - kMeshBytesPerTriangle));
    return std::max(beside, f.mesh);
}

Peak stage_peak(const MemoryFacts& f, bool tiled) {
    // The OpenCL runtime, once loaded, stays to the end. Tiles making the surface hold
    // their parts as they run, then the welded mesh beside them (no larger), and no field
    // after.
    const std::size_t solve = (tiled ? f.field + f.surfaces + f.tile_solver : f.whole_solver) + f.runtime;
    const std::size_t weld = f.surfaces ? f.field + 2 * f.surfaces + f.runtime : 0;
    const std::size_t mesh = mesh_stage(f, f.surfaces ? 0 : f.field) + f.runtime;
    if (solve >= mesh && solve >= weld) return {f.grid + solve, tiled ? "the largest tile's solver" : "the solver"};
    if (weld > mesh) return {f.grid + weld, "the tiles' surfaces as they are welded"};
    return {f.grid + mesh, "the mesh and its check"};
}

// The share of a tiled run's bricks next to its cores' faces (a brick layer each side),
// which it keeps of the field when its tiles make the surface.
double face_share(int cells) {
    const double inner = std::max(0.0, double(cells - 2 * kBrick) / double(cells));
    return 1 - inner * inner * inner;
}

}  // namespace

MemoryChoice fit_memory(const PointCloud& measured, const DomainPlan& plan, const Parameters& params) {
    MemoryChoice choice;
    MemoryFacts& f = choice.facts;
    const std::size_t real = params.precision == Precision::Double ? 8 : 4;
    const Domain& d = plan.domain;
    const NearBricks near(detail::tree_of(measured), d, band_reach(plan, params));
    f.near_bricks = near.count();

    f.whole_solver = solver_bytes(f.near_bricks, real);
    const std::size_t field = f.near_bricks * kBrickCells * real;
    f.field = field;
    const std::size_t triangles = f.near_bricks * kTrianglesPerBrick;
    f.mesh = triangles * kCheckBytesPerTriangle + measured.size() * kCheckBytesPerPoint;
    f.grid = plan.estimated_bytes;
    f.runtime = params.device == "openmp" ? 0 : kDeviceRuntimeBytes;
    f.budget_given = bool(params.max_memory);
    // Under a budget, what the run added; without, what the process holds (beside what is free).
    f.held = f.budget_given ? detail::budget_used() : detail::resident_bytes();
    const std::size_t room = f.budget_given ? *params.max_memory - std::min(*params.max_memory, f.held)
                                            : detail::available_memory() / 10 * 9;
    f.budget = f.budget_given ? *params.max_memory : f.held + room;

    bool derived = true;
    const int halo = tile_halo(plan, params, derived);
    const int longest = std::max({d.nx, d.ny, d.nz});
    const auto tile_solver = [&](int cells) {
        const std::vector<Tile> tiles = plan_tiles(d, cells, halo);
        Tile largest;
        for (int a = 0; a < 3; ++a) largest.hi[std::size_t(a)] = std::min(cells + 2 * halo, a == 0 ? d.nx : a == 1 ? d.ny : d.nz);
        return solver_bytes(near.most_in_a_tile(tiles, d, cells, halo), real) + estimate_plan_bytes(tile_domain(d, largest));
    };
    const auto settle = [&](int cells, bool by_budget) {
        choice.tile_cells = cells;
        f.tiled_by_budget = by_budget;
        f.tile_solver = cells ? tile_solver(cells) : 0;
        const bool surfaces = cells > 0 && !params.whole_field;
        f.field = surfaces ? std::size_t(double(field) * face_share(cells)) : field;
        f.surfaces = surfaces ? triangles * kSurfaceBytesPerTriangle : 0;
        const Peak peak = stage_peak(f, cells > 0);
        f.estimated_peak = f.held + peak.bytes;
        f.bound = f.held > peak.bytes ? "the points" : peak.what;
        return peak.bytes <= room;
    };

    if (params.tile_cells > 0) {
        if (!settle(params.tile_cells, false) && f.budget_given)
            throw ResourceError("tiles of " + std::to_string(params.tile_cells) + " cells (--tile-cells) need about " +
                                gib(f.estimated_peak) + " at their peak (" + f.bound + "), over the memory budget of " +
                                gib(f.budget) + " (--max-memory): give smaller tiles or a larger budget");
        return choice;
    }
    if (settle(0, false)) return choice;
    const std::size_t whole_peak = f.estimated_peak;
    for (int cells = 512; cells >= 32; cells /= 2)
        if (cells < longest && settle(cells, true)) return choice;
    if (!f.budget_given) {  // the memory model may be wrong: the run tries whole, as before
        settle(0, false);
        return choice;
    }
    // Nothing fits: name what tiles cannot shrink.
    std::string why;
    const bool field_kept = params.whole_field;  // in tiles making the surface, the field shrinks with them
    if (f.held + f.grid + mesh_stage(f, field_kept ? field : 0) + f.runtime > f.budget)
        why = "the points take " + gib(f.held) + " (" + std::to_string(measured.size()) + " filed), " +
              (field_kept ? "the phase field for the mesh " + gib(field) + ", " : std::string()) +
              "the mesh and its check about " + gib(f.mesh) + ", the grid's tables " + gib(f.grid) +
              (f.runtime ? " and the OpenCL runtime " + gib(f.runtime) : std::string()) + ", which tiles do not shrink";
    else
        why = "the smallest tiles (32 cells) would still need about " + gib(f.estimated_peak);
    throw ResourceError("the run needs about " + gib(whole_peak) + " whole, over the memory budget of " + gib(f.budget) +
                        " (--max-memory): " + why + "; give a larger budget, a coarser --resolution or a larger --voxel");
}

}  // namespace snvr
