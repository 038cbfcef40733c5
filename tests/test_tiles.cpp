// Tiled runs (Parameters::tile_cells): the halo derived from the flow, and the shell of a
// run cut into tiles the whole run's shell (every vertex within 0.01 voxels, the same
// pieces, genus and enclosure) on shapes that cross tiles' corners and lie on their
// faces, with a cluster of strays split by a face; a halo narrower than the flow's reach
// shows.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>

#include "snvr/error.hpp"
#include "snvr/point_io.hpp"
#include "snvr/quality.hpp"
#include "snvr/shapes.hpp"
#include "snvr/shell.hpp"
#include "mesh/dual_pieces.hpp"
#include "solver/field_assembly.hpp"
#include "geometry/point_tree.hpp"
#include "mesh/fair_and_keep_deep.hpp"
#include "mesh/guard_search.hpp"
#include "solver/plan_guard.hpp"
#include "solver/slab_surface.hpp"
#include "solver/tile_needs.hpp"
#include "solver/tile_plan.hpp"
#include "solver/tile_surface.hpp"

using namespace snvr;

namespace {

// Each tile's part of a run's surface in slices, as a run over processes cuts it.
std::vector<detail::MeshPiece> sliced_tile_surfaces(const Result& run, int cells) {
    std::vector<detail::MeshPiece> pieces;
    for (const Tile& t : plan_tiles(run.domain, cells, 8))
        for (detail::MeshPiece& piece : tile_surface(detail::field_part(run.phi, t.lo, t.hi), t, run.domain, kSlabSlice))
            pieces.push_back(std::move(piece));
    return pieces;
}
// A mesh's vertices by the plane they lie in (to plan slabs on).
std::vector<std::uint64_t> vertices_by_plane(const Mesh& mesh, const Domain& d) {
    std::vector<std::uint64_t> by_plane(std::size_t(d.nz), 0);
    for (const Vec3& v : mesh.vertices) ++by_plane[std::size_t((v[2] - d.origin[2]) / d.h)];
    return by_plane;
}

// The points of a tree with z in [lo, hi], in its order and frame, as a slab's guard gets them.
PointCloud window_cloud(const detail::PointTree& tree, double lo, double hi) {
    const std::vector<PointRuns> runs = z_window_runs(tree, {{lo, hi}});
    detail::PointArray<float> flat = points_in(tree, runs[0]);
    return detail::cloud_of_flat(std::vector<float>(flat.begin(), flat.end()), tree.origin, &tree.frame());
}

Shell shell_of(const PointSet& points, int resolution, int tile_cells, std::optional<int> halo = {}) {
    ShellSettings s;
    s.params.resolution = resolution;
    s.params.device = "openmp";
    s.params.tile_cells = tile_cells;
    s.params.tile_halo_cells = halo;
    return make_shell(points, s);
}

// The tiled shell against the whole one: the same solid, every vertex within `most` voxels.
void same_shell(const Shell& whole, const Shell& tiled, double most = 0.01) {
    CHECK(tiled.run.tiles.core_cells > 0);
    CHECK(tiled.quality.report.components == whole.quality.report.components);
    CHECK(tiled.quality.solids == whole.quality.solids);
    CHECK(tiled.quality.genus == whole.quality.genus);
    CHECK(tiled.quality.points_inside == whole.quality.points_inside);
    CHECK(tiled.mesh.triangles.size() == whole.mesh.triangles.size());
    const VertexDistance d = vertex_distance(whole.mesh, tiled.mesh);
    CAPTURE(d.max / whole.run.domain.h);
    CHECK(d.max <= most * whole.run.domain.h);
}

// The points whole and in tiles of 16 on the unit box in 64 cells (h = 1/64, no padding):
// tiles' faces at 0.25, 0.5 and 0.75.
std::pair<Shell, Shell> whole_and_tiled_in_unit_box(const PointSet& points) {
    ShellSettings s;
    s.params.resolution = 64;
    s.params.box = std::array<Vec3, 2>{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
    s.params.device = "openmp";
    Shell whole = make_shell(points, s);
    s.params.tile_cells = 16;
    return {std::move(whole), make_shell(points, s)};
}

FlowReach defaults_flow() {
    // The defaults: 6 steps of h^2 / 4, eps 12 cells' width (1.60 h), xi 4 (0.53 h).
    FlowReach f;
    f.dt_cells = 0.25;
    f.steps = 6;
    const double eps = eps_of_cells(12, 1.0);
    f.rate = 2 * f.dt_cells / (eps * eps);
    f.width_cells = eps;
    return f;
}

}  // namespace

TEST_CASE("flow_halo_cells: a few cells at the defaults, wider for a longer flow or longer steps, none without steps") {
    const FlowReach flow = defaults_flow();
    const int halo = flow_halo_cells(flow, 1e-3);
    CHECK(halo >= 8);
    CHECK(halo <= 16);
    FlowReach longer = flow;
    longer.steps = 24;  // --smoothing 6
    CHECK(flow_halo_cells(longer, 1e-3) > halo);
    FlowReach wider = flow;
    wider.dt_cells = 1;  // --dt-cells 1: a quarter of the steps, each reaching farther
    wider.steps = 2;
    CHECK(flow_halo_cells(wider, 1e-3) > flow_halo_cells({1, 2, flow.rate * 4, flow.width_cells}, 1e-2));
    FlowReach none = flow;
    none.steps = 0;
    CHECK(flow_halo_cells(none, 1e-3) == 0);
    // A looser bound needs less.
    CHECK(flow_halo_cells(flow, 1e-1) < halo);
}

TEST_CASE("plan_tiles: cores cover the grid once, halos clipped to it, the tile's grid on the whole one's lattice") {
    Domain whole;
    whole.nx = 80;
    whole.ny = 64;
    whole.nz = 48;
    whole.h = 0.5;
    whole.origin = {1, 2, 3};
    whole.levels = 4;
    const std::vector<Tile> tiles = plan_tiles(whole, 32, 16);
    CHECK(tiles.size() == 3 * 2 * 2);
    std::size_t covered = 0;
    for (const Tile& t : tiles) {
        std::size_t core = 1;
        for (int a = 0; a < 3; ++a) {
            core *= std::size_t(t.core_hi[std::size_t(a)] - t.core_lo[std::size_t(a)]);
            CHECK(t.lo[std::size_t(a)] == std::max(0, t.core_lo[std::size_t(a)] - 16));
            CHECK(t.lo[std::size_t(a)] % 8 == 0);
        }
        covered += core;
    }
    CHECK(covered == whole.cells());
    const Tile& last = tiles.back();  // x 64-80, y 32-64, z 32-48
    CHECK(last.hi[0] == 80);
    CHECK(last.lo[0] == 48);
    const Domain d = tile_domain(whole, last);
    CHECK(d.nx == 32);
    CHECK(d.ny == 48);
    CHECK(d.nz == 32);
    CHECK(d.origin[0] == doctest::Approx(1 + 48 * 0.5));
    CHECK(d.h == whole.h);
    CHECK(d.levels >= 2);
    CHECK(d.nx % (1 << (d.levels - 1)) == 0);
    CHECK(d.ny % (1 << (d.levels - 1)) == 0);
}

TEST_CASE("the bunny in tiles: the whole run's shell; with no halo, not") {
    const PointSet bunny = read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply");
    const Shell whole = shell_of(bunny, 128, 0);
    const Shell tiled = shell_of(bunny, 128, 64);
    CHECK(tiled.run.tiles.tiles == 8);
    CHECK(tiled.run.tiles.halo_derived);
    CHECK(tiled.run.tiles.halo_cells == 16);
    same_shell(whole, tiled);
    // The flow reaches across the tile's edge: cut there, the shell moves by most of a voxel.
    const Shell cut = shell_of(bunny, 128, 64, 0);
    CHECK_FALSE(cut.run.tiles.halo_derived);
    CHECK(vertex_distance(whole.mesh, cut.mesh).max > 0.1 * whole.run.domain.h);
}

TEST_CASE("tiles that stop sooner run again: every tile as many V-cycles in each step as the one that took most") {
    // At tol 1e-4 some of the bunny's tiles need a second V-cycle in a step where others
    // need one: those run again with two.
    const PointSet bunny = read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply");
    ShellSettings s;
    s.params.resolution = 128;
    s.params.device = "openmp";
    s.params.tol = 1e-4;
    const Shell whole = make_shell(bunny, s);
    s.params.tile_cells = 64;
    const Shell tiled = make_shell(bunny, s);
    CHECK(tiled.run.tiles.reruns > 0);
    int most = 0;
    for (const StepStats& st : tiled.run.steps) most = std::max(most, st.cycles);
    CHECK(most == 2);
    CHECK(tiled.quality.genus == whole.quality.genus);
    CHECK(tiled.quality.solids == whole.quality.solids);
    CHECK(tiled.quality.points_inside == whole.quality.points_inside);
    // The whole run's stopping (its RMS over every cell) took a second cycle in fewer
    // steps: the shells differ by the solve's tolerance, not by the tiles.
    CHECK(vertex_distance(whole.mesh, tiled.mesh).rms <= 0.01 * whole.run.domain.h);
}

TEST_CASE("shapes across tiles: sheets through tile corners, a rod on a tile face, a small piece beside it, empty tiles") {
    SUBCASE("two sheets and a Moebius strip, tiles of 16 at 64 cells (corners everywhere)") {
        for (const char* shape : {"sheets", "mobius"}) {
            CAPTURE(shape);
            const PointSet points = shapes::by_name(shape, 0.01);
            same_shell(shell_of(points, 64, 0), shell_of(points, 64, 16));
        }
    }
    SUBCASE("a thin rod lying on a tile face, a small sphere within the next tile's halo, most tiles empty") {
        // The grid: the unit box in 64 cells (h = 1/64, no padding), tiles' faces at 0.25, 0.5, 0.75.
        PointSet points = shapes::sphere({0.45, 0.45, 0.4}, 0.15, 0.01);
        for (double y = 0.3; y <= 0.7; y += 0.002) points.push_back({0.5, y, 0.8});  // on the face x = 0.5
        const PointSet ball = shapes::sphere({0.5 + 4.0 / 64, 0.75, 0.72}, 0.02, 0.005);
        points.insert(points.end(), ball.begin(), ball.end());
        const auto [whole, tiled] = whole_and_tiled_in_unit_box(points);
        CHECK(whole.run.domain.h == 1.0 / 64);
        CHECK(whole.quality.solids == 3);
        CHECK(tiled.run.tiles.tiles == 64);
        CHECK(tiled.run.tiles.run < tiled.run.tiles.tiles);
        same_shell(whole, tiled);
    }
}

TEST_CASE("the tiles make the surface: the mesh of the field their cores make, bit for bit, without that field") {
    // Shapes across tile corners and faces, tiles of 16 (seams everywhere) and of 24 (the
    // seams' words of 64 samples split between tiles), in float and in double.
    for (const char* shape : {"sheets", "mobius", "torus"})
        for (int cells : {16, 24})
            for (Precision precision : {Precision::Single, Precision::Double}) {
                CAPTURE(shape);
                CAPTURE(cells);
                const PointSet points = shapes::by_name(shape, 0.01);
                Parameters p;
                p.resolution = 64;
                p.device = "openmp";
                p.precision = precision;
                p.tile_cells = cells;
                const Result field = reconstruct(points, p);
                p.whole_field = false;
                const Result surface = reconstruct(points, p);
                CHECK_FALSE(field.surface_made);
                REQUIRE(surface.surface_made);
                CHECK(surface.phi.stored_bricks() == 0);
                CHECK(surface.active_bricks == field.active_bricks);
                const Mesh whole = extract_dual_isosurface(field.phi, field.domain);
                REQUIRE(whole.triangles.size() > 1000);
                CHECK(surface.surface.vertices == whole.vertices);
                CHECK(surface.surface.triangles == whole.triangles);
                // Alone, the fairing is the mesher's (several processes fair it in slabs: below).
                p.surface_fairing = MeshFairing{};
                const Result alone = reconstruct(points, p);
                CHECK_FALSE(alone.surface_faired);
                CHECK(alone.surface.vertices == whole.vertices);
            }
    // make_shell makes it so unless the field is kept: the same shell either way.
    const PointSet bunny = read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply");
    ShellSettings s;
    s.params.resolution = 128;
    s.params.device = "openmp";
    s.params.tile_cells = 32;
    const Shell made = make_shell(bunny, s);
    s.keep_field = true;
    const Shell kept = make_shell(bunny, s);
    CHECK(made.run.surface_made);
    CHECK_FALSE(kept.run.surface_made);
    CHECK(made.mesh.vertices == kept.mesh.vertices);
    CHECK(made.mesh.triangles == kept.mesh.triangles);
}

TEST_CASE("the surface in slabs of planes: the slabs in turn are the whole mesh faired, bit for bit; a ghost plane fewer, not") {
    // The tiles' parts and seams of a whole run's field (its bricks stand for the faces'),
    // welded and faired slab by slab as the processes of a run do (shared_slabs.cpp), then
    // joined: one slab, a few, and more slabs than planes of ghosts (thin and empty ones).
    for (const char* shape : {"sheets", "torus", "mobius"}) {
        CAPTURE(shape);
        Parameters p;
        p.resolution = 64;
        p.device = "openmp";
        const Result run = reconstruct(shapes::by_name(shape, 0.01), p);
        const Domain& d = run.domain;
        const MeshFairing fairing;  // the default passes
        Mesh whole = extract_dual_isosurface(run.phi, d);
        fair_mesh(whole, fairing);
        const int cells = 16;
        const std::vector<std::uint64_t> by_plane = vertices_by_plane(whole, d);
        const std::vector<detail::MeshPiece> pieces = sliced_tile_surfaces(run, cells);
        const FacesPart faces{run.phi, 0};
        for (int slabs : {1, 2, 3, 40})
            for (int fewer : {0, 1}) {
                CAPTURE(slabs);
                CAPTURE(fewer);
                const SlabPlan plan = plan_slabs(by_plane, slabs, slab_ghost_planes(fairing) - fewer);
                REQUIRE(plan.slabs() == slabs);
                Mesh joined;
                for (int s = 0; s < slabs; ++s) {
                    std::vector<detail::MeshPiece> given = pieces;
                    const Mesh own = slab_own(weld_slab(given, faces, d, cells, plan, s, fairing), joined.vertices.size());
                    joined.vertices.insert(joined.vertices.end(), own.vertices.begin(), own.vertices.end());
                    joined.triangles.insert(joined.triangles.end(), own.triangles.begin(), own.triangles.end());
                }
                CHECK(joined.triangles == whole.triangles);
                if (fewer && slabs > 1) CHECK(joined.vertices != whole.vertices);
                else CHECK(joined.vertices == whole.vertices);
            }
    }
}

TEST_CASE("the depth guard in slabs: the slabs in turn are the whole guarded mesh with its report; ghosts too few show in the check") {
    // The bunny at 96 cells, whose guard lifts 1,513 vertices: faired and guarded slab by
    // slab as the processes of a run do (shared_slabs.cpp: the first slab with the whole
    // tree, the others with the points near their planes, in its frame and order).
    const PointCloud bunny(read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply"));
    Parameters p;
    p.resolution = 96;
    p.device = "openmp";
    const Result run = reconstruct(bunny, p);
    const Domain& d = run.domain;
    const detail::KeepDeep deep = detail::keep_deep_of(run);
    REQUIRE(detail::has_inner_wall(run));
    const MeshFairing fairing;
    Mesh whole = extract_dual_isosurface(run.phi, d);
    const DepthGuardReport guard = detail::fair_and_keep_deep(whole, bunny, fairing, &deep);
    REQUIRE(guard.moved_vertices > 1000);
    const detail::PointTree& tree = detail::tree_of(bunny);
    const int cells = 32;
    const std::vector<detail::MeshPiece> pieces = sliced_tile_surfaces(run, cells);
    const std::vector<std::uint64_t> by_plane = vertices_by_plane(whole, d);
    const FacesPart faces{run.phi, 0};
    const int reach = detail::guard_reach_planes(deep.depth, deep.voxel);
    REQUIRE(reach == 8);  // 2 voxels deep at the defaults
    REQUIRE(slab_ghost_planes(fairing, &deep) == 16);  // after the fairing's 4, and 4 checked
    // The ghosts as a run has them; then as few as the fairing's with half of them checked.
    for (const int ghost : {slab_ghost_planes(fairing, &deep), 4})
        for (const int slabs : {2, 3}) {
            CAPTURE(ghost);
            CAPTURE(slabs);
            SlabPlan plan = plan_slabs(by_plane, slabs, ghost);
            plan.checked = ghost == 4 ? 2 : guard_checked_planes(deep);
            const double point_reach = detail::guard_point_reach(deep.depth, deep.voxel, deep.lone);
            Mesh joined;
            DepthGuardReport summed;
            std::vector<SlabBands> bands;
            std::vector<std::size_t> firsts;
            for (int s = 0; s < slabs; ++s) {
                const detail::Planes planes = plan.welded(s);
                const PointCloud near =
                    window_cloud(tree, d.origin[2] + planes.lo * d.h - point_reach, d.origin[2] + planes.hi * d.h + point_reach);
                std::vector<detail::MeshPiece> given = pieces;
                SlabWeld w = weld_slab(given, faces, d, cells, plan, s, fairing, &deep,
                                       s == 0 ? &tree : &detail::tree_of(near));
                summed.near_vertices += w.guard.near_vertices;
                summed.moved_vertices += w.guard.moved_vertices;
                summed.shallow_points += w.guard.shallow_points;
                summed.lone_points += w.guard.lone_points;
                summed.repair_rounds = std::max(summed.repair_rounds, w.guard.repair_rounds);
                bands.push_back(slab_bands(w));
                firsts.push_back(joined.vertices.size());
                const Mesh own = slab_own(std::move(w), joined.vertices.size());
                joined.vertices.insert(joined.vertices.end(), own.vertices.begin(), own.vertices.end());
                joined.triangles.insert(joined.triangles.end(), own.triangles.begin(), own.triangles.end());
            }
            REQUIRE(joined.triangles == whole.triangles);
            std::size_t differ = 0;
            for (int s = 0; s < slabs; ++s) {
                const std::size_t own = (s + 1 < slabs ? firsts[std::size_t(s) + 1] : joined.vertices.size()) - firsts[std::size_t(s)];
                differ += bands_differing(bands[std::size_t(s)], joined.vertices, firsts[std::size_t(s)], own);
            }
            if (ghost == 4) {
                // Too few: own vertices differ from the whole guard's, and the check sees it.
                CHECK(joined.vertices != whole.vertices);
                CHECK(differ > 0);
                continue;
            }
            CHECK(differ == 0);
            CHECK(joined.vertices == whole.vertices);
            CHECK(summed.near_vertices == guard.near_vertices);
            CHECK(summed.moved_vertices == guard.moved_vertices);
            CHECK(summed.shallow_points == guard.shallow_points);
            CHECK(summed.lone_points == guard.lone_points);
            CHECK(summed.repair_rounds == guard.repair_rounds);
        }
}

TEST_CASE("a cluster of stray points split by a tile face: dropped alike, the same shell") {
    // The unit box in 64 cells, tiles of 16: faces at x = 0.25, 0.5, 0.75.
    PointSet points = shapes::sphere({0.45, 0.45, 0.45}, 0.2, 0.01);
    for (int i = 0; i < 6; ++i) points.push_back({0.5 + (i - 2.5) * 0.002, 0.85, 0.85});  // 6 strays across x = 0.5
    const auto [whole, tiled] = whole_and_tiled_in_unit_box(points);
    CHECK(whole.outliers.points.size() >= 6);
    CHECK(tiled.outliers.points == whole.outliers.points);
    CHECK(whole.quality.solids == 1);
    same_shell(whole, tiled);
}

TEST_CASE("FieldAssembly: cores placed into the whole grid's bricks, constants shared, a core placed again replaced") {
    Domain whole;
    whole.nx = whole.ny = whole.nz = 16;
    Tile t;  // the tile is the whole grid; its core the brick at (1, 0, 0) and the one at (1, 1, 0)
    t.core_lo = {8, 0, 0};
    t.core_hi = {16, 16, 8};
    t.lo = {0, 0, 0};
    t.hi = {16, 16, 16};
    // A session's field: the constant bricks 0, +1, -1 in the first slots, then its own.
    const auto tile_field = [](float value) {
        std::vector<float> stored(4 * Field::kBrickCells, 0.0f);
        std::fill(stored.begin() + Field::kBrickCells, stored.begin() + 2 * Field::kBrickCells, 1.0f);
        std::fill(stored.begin() + 2 * Field::kBrickCells, stored.begin() + 3 * Field::kBrickCells, -1.0f);
        std::fill(stored.begin() + 3 * Field::kBrickCells, stored.end(), value);
        //            x 0 1 (y 0)  x 0 1 (y 1)   z 1: all +1
        return Field::from_bricks(16, 16, 16, {2, 3, 2, 1, 1, 1, 1, 1}, stored);
    };
    FieldAssembly<float> assembly(whole);
    assembly.place(tile_field(0.25f), t);
    assembly.place(tile_field(0.5f), t);  // the same core again
    const Field f = assembly.take();
    CHECK(f.at(9, 3, 3) == 0.5f);    // the core's own brick, replaced
    CHECK(f.at(12, 12, 3) == 1.0f);  // the core's constant +1 brick
    CHECK(f.at(3, 3, 3) == -1.0f);   // outside the core: -1
    CHECK(f.at(3, 3, 12) == -1.0f);
    CHECK(f.stored_bricks() == 3 + 1);  // the constants and the core's one brick, once
}

TEST_CASE("one tile over the whole grid is the whole run, bit for bit; a cancel between tiles stops the run") {
    const PointSet points = shapes::by_name("torus", 0.02);
    const Shell whole = shell_of(points, 64, 0);
    const Shell one = shell_of(points, 64, 256);
    CHECK(one.run.tiles.tiles == 1);
    CHECK(one.mesh.vertices == whole.mesh.vertices);
    CHECK(one.mesh.triangles == whole.mesh.triangles);
    ShellSettings s;
    s.params.resolution = 64;
    s.params.device = "openmp";
    s.params.tile_cells = 16;
    int tiles_seen = 0;
    CHECK_THROWS_AS(make_shell(points, s, [&](const Progress& p) { return !(p.stage == "tile" && ++tiles_seen == 3); }),
                    Cancelled);
    CHECK(tiles_seen == 3);
}

TEST_CASE("a tile that fails names the tile; nothing comes back") {
    ::setenv("SNVR_TEST_TILE_FAULT", "first", 1);
    std::string message;
    try {
        shell_of(shapes::sphere({0.45, 0.45, 0.45}, 0.2, 0.01), 64, 16);
    } catch (const ResourceError& e) {
        message = e.what();
    }
    ::unsetenv("SNVR_TEST_TILE_FAULT");
    CAPTURE(message);
    CHECK(message.rfind("tile ", 0) == 0);
    CHECK(message.find(" (cells ") != std::string::npos);
    CHECK(message.find("): a test fault (SNVR_TEST_TILE_FAULT)") != std::string::npos);
}

TEST_CASE("a tile's warning names the tile") {
    ShellSettings s;
    s.params.resolution = 64;
    s.params.device = "openmp";
    s.params.tile_cells = 32;
    s.params.tol = 1e-9;  // out of reach in one V-cycle
    s.params.max_cycles = 1;
    const Shell shell = make_shell(shapes::by_name("torus", 0.02), s);
    bool named = false;
    for (const std::string& w : shell.warnings)
        named = named || (w.rfind("tile 0 (cells 0-32, 0-32, 0-32): ", 0) == 0 && w.find("steps did not converge") != std::string::npos);
    CHECK(named);
}
