// The memory budget (Parameters::max_memory, lib/src/solver/memory_budget.hpp): a run
// that fits goes whole, its estimates above what it took; one whose solver does not fit
// whole goes in tiles, the whole run's shell; one whose field or mesh cannot fit stops
// before its long part with an error naming them; points beyond it go to files, the same
// shell; snvr-cl reads the budget's sizes.
#include <doctest/doctest.h>

#include <string>

#include "process_limits.hpp"
#include "snvr/error.hpp"
#include "snvr/point_io.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"
#include "snvr/shell.hpp"
#include "cli_run.hpp"

using namespace snvr;
using namespace cli_testing;

namespace {

const std::string kBunny = std::string(SNVR_DATA_DIR) + "/bunny.ply";

ShellSettings bunny_settings(int resolution, std::optional<std::size_t> budget) {
    ShellSettings s;
    s.params.resolution = resolution;
    s.params.device = "openmp";
    s.params.precision = Precision::Double;  // the solver's four fields weigh most: tiles matter
    s.params.max_memory = budget;
    return s;
}

std::string error_of(const PointCloud& points, const ShellSettings& s) {
    try {
        make_shell(points, s);
    } catch (const ResourceError& e) {
        return e.what();
    }
    return "";
}

constexpr std::size_t kMiB = std::size_t(1) << 20;

}  // namespace

TEST_CASE("a budget the whole run fits: whole; the estimates hold what it took") {
    const PointCloud points(read_points(kBunny));
    Parameters p = bunny_settings(128, std::size_t(4) << 30).params;
    const Result r = reconstruct(points, p);
    const MemoryFacts& m = r.memory;
    CHECK(r.tiles.core_cells == 0);
    CHECK(m.budget_given);
    CHECK(m.budget == std::size_t(4) << 30);
    CHECK(!m.tiled_by_budget);
    CHECK(m.near_bricks >= r.active_bricks);  // every band brick is near a point
    CHECK(m.whole_solver >= r.solver_bytes);
    CHECK(m.field >= r.phi.bytes());
    CHECK(m.runtime == 0);  // OpenMP loads no runtime
    CHECK(m.estimated_peak <= m.budget);
    CHECK(!m.bound.empty());
    // No budget: the memory available decides, and it is reported as the room.
    p.max_memory.reset();
    const Result free = reconstruct(points, p);
    CHECK(!free.memory.budget_given);
    CHECK(free.memory.budget > free.memory.held);
    CHECK(free.tiles.core_cells == 0);
}

TEST_CASE("a budget the solver does not fit whole: the largest tiles that fit, the whole run's shell") {
    const PointCloud points(read_points(kBunny));
    const Shell whole = make_shell(points, bunny_settings(256, std::size_t(4) << 30));
    const MemoryFacts& m = whole.run.memory;
    REQUIRE(whole.run.tiles.core_cells == 0);
    // Between what tiles need (the field, the mesh and its check) and what the whole
    // solver needs: half way, as the run holds about what it held here.
    const std::size_t tiles_need = m.held + m.grid + m.field + m.mesh, whole_needs = m.held + m.grid + m.whole_solver;
    REQUIRE(whole_needs > tiles_need + 20 * kMiB);
    const std::size_t budget = (tiles_need + whole_needs) / 2;
    const Shell tiled = make_shell(points, bunny_settings(256, budget));
    CAPTURE(tiled.run.memory.bound);
    CHECK(tiled.run.memory.tiled_by_budget);
    CHECK(tiled.run.tiles.core_cells > 0);
    CHECK(tiled.run.tiles.core_cells < 256);
    CHECK(tiled.run.memory.estimated_peak <= budget);
    CHECK(tiled.run.memory.tile_solver > 0);
    CHECK(tiled.run.memory.tile_solver < m.whole_solver);
    // Tiles compute what the whole run computes.
    CHECK(tiled.quality.solids == whole.quality.solids);
    CHECK(tiled.quality.genus == whole.quality.genus);
    CHECK(tiled.quality.points_inside == whole.quality.points_inside);
    const VertexDistance d = vertex_distance(whole.mesh, tiled.mesh);
    CHECK(d.max <= 0.01 * whole.run.domain.h);
    // Tiles given and too large for the budget: refused, naming the option.
    ShellSettings probe = bunny_settings(256, std::size_t(4) << 30);
    probe.params.tile_cells = 128;
    const std::size_t at_128 = make_shell(points, probe).run.memory.estimated_peak;
    ShellSettings given = bunny_settings(256, at_128 - 16 * kMiB);
    given.params.tile_cells = 128;
    const std::string e = error_of(points, given);
    CAPTURE(e);
    CHECK(e.find("tiles of 128 cells (--tile-cells)") != std::string::npos);
    CHECK(e.find("--max-memory") != std::string::npos);
}

TEST_CASE("a budget nothing fits: stopped before the distance, naming what tiles do not shrink") {
    const PointCloud points(read_points(kBunny));
    const std::string e = error_of(points, bunny_settings(512, 64 * kMiB));
    CAPTURE(e);
    CHECK(e.find("over the memory budget of 0.0625 GiB (--max-memory)") != std::string::npos);
    CHECK(e.find("the mesh and its check") != std::string::npos);
    CHECK(e.find("which tiles do not shrink") != std::string::npos);
    // The budget is lifted when the call ends, by its error too.
    CHECK(detail::budget_in_force() == 0);
    // Below the least budget: a parameter error.
    ShellSettings tiny = bunny_settings(128, 10 * kMiB);
    CHECK_THROWS_AS(make_shell(points, tiny), ParameterError);
}

TEST_CASE("snvr-cl --max-memory: sizes read in powers of 1024, a budget too small an error and no output") {
    TempDir t;
    const std::string cli = SNVR_CLI;
    Run bad = run_command(cli + " reconstruct " + kBunny + " -o " + t.out() + " --max-memory 2X 2>&1; echo rc=$?");
    CHECK(bad.output.find("bad value '2X' for --max-memory") != std::string::npos);
    bad = run_command(cli + " reconstruct " + kBunny + " -o " + t.out() + " --max-memory -1G 2>&1; echo rc=$?");
    CHECK(bad.output.find("bad value '-1G' for --max-memory") != std::string::npos);
    const Run small = run_command(cli + " reconstruct " + kBunny + " -o " + t.out() +
                                  " --resolution 512 --max-memory 0.0625GiB 2>&1; echo rc=$?");
    CAPTURE(small.output);
    CHECK(small.output.find("rc=1\n") != std::string::npos);
    CHECK(small.output.find("over the memory budget of 0.0625 GiB") != std::string::npos);
    CHECK(!fs::exists(t.out()));
    const Run fits = run_command(cli + " reconstruct " + kBunny + " -o " + t.out() +
                                 " --resolution 64 --max-memory 512M --report " + t.file("r.json", "") + " 2>&1; echo rc=$?");
    CAPTURE(fits.output);
    CHECK(fits.output.find("rc=0") != std::string::npos);
    CHECK(fits.output.find("budget 512.0 MiB (--max-memory)") != std::string::npos);
    CHECK(fs::exists(t.out()));
}

TEST_CASE("snvr-cl: points beyond the budget go to files in the temporary folder, the same shell, none left") {
    TempDir t;
    const std::string cloud = (t.path / "sphere.ply").string();
    write_points(shapes::noisy_sphere({0, 0, 0}, 0.35, 0.0009, 0.0002), cloud);  // 2 M points, 24 MB as floats
    const fs::path temp = t.path / "temp";
    fs::create_directories(temp);
    const std::string cli = SNVR_CLI;
    const std::string run = cli + " reconstruct " + cloud + " --resolution 64 --device openmp --units m";
    const Run whole = run_command(run + " -o " + (t.path / "whole.stl").string() + " --quiet 2>&1; echo rc=$?");
    CAPTURE(whole.output);
    REQUIRE(whole.output.find("rc=0") != std::string::npos);
    // A sixteenth of 96 MiB: the coordinates, their input places, keys and nodes go to files.
    const Run spilled = run_command(run + " -o " + (t.path / "spilled.stl").string() + " --max-memory 96M --temp-dir " +
                                    temp.string() + " 2>&1; echo rc=$?");
    CAPTURE(spilled.output);
    REQUIRE(spilled.output.find("rc=0") != std::string::npos);
    CHECK(spilled.output.find("the points beyond the budget in files:") != std::string::npos);
    CHECK(spilled.output.find("in " + temp.string()) != std::string::npos);
    CHECK(run_command("cmp " + (t.path / "whole.stl").string() + " " + (t.path / "spilled.stl").string() +
                      " && echo same").output.find("same") != std::string::npos);
    CHECK(fs::is_empty(temp));
}
