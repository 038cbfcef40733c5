// make_shell, the library's whole job: the same bytes as snvr-cl writes, the outliers and
// the check it reports, its refusals, and a progress callback that cancels.
#include <doctest/doctest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"
#include "snvr/report.hpp"
#include "snvr/shapes.hpp"
#include "snvr/shell.hpp"

namespace fs = std::filesystem;
using namespace cli_testing;

namespace {

std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

snvr::ShellSettings small(const std::string& written_as = ".stl") {
    snvr::ShellSettings s;
    s.params.resolution = 32;
    s.params.device = "openmp";
    s.written_as = written_as;
    return s;
}

}  // namespace

TEST_CASE("make_shell writes what snvr-cl writes, byte for byte, and reports what it prints") {
    TempDir t;
    snvr::PointSet points = snvr::shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03);
    const std::size_t surface = points.size();
    // Two far strays for the outlier rules.
    points.push_back({3, 3, 3});
    points.push_back({-2, 0.5, 4});
    const std::string input = (t.path / "in.ply").string();
    snvr::write_points(points, input);  // binary float: what both read is the same

    const Run r = run("reconstruct " + input + " -o " + t.out() + " --resolution 32 --device openmp --quiet");
    REQUIRE(r.code == 0);
    const snvr::Shell shell = snvr::make_shell(snvr::read_point_cloud(input), small());
    const std::string mine = (t.path / "mine.stl").string();
    snvr::write_mesh(shell.mesh, mine);
    CHECK(bytes_of(mine) == bytes_of(t.out()));

    CHECK(shell.outliers.points.size() == 2);
    CHECK(shell.outliers.input_indices == std::vector<std::size_t>{surface, surface + 1});
    CHECK(shell.points == surface);
    CHECK(shell.quality.points_inside == surface);
    CHECK(shell.quality.report.closed());
    CHECK(shell.clusters == 1);
    CHECK(shell.run.phi.stored_bricks() == 0);  // freed before the check unless kept
    CHECK(shell.seconds.total > 0);

    snvr::ShellSettings all = small();
    all.drop_outliers = false;
    all.keep_field = true;
    const snvr::Shell every = snvr::make_shell(points, all);
    CHECK(every.outliers.points.empty());
    CHECK(every.points == points.size());
    CHECK(every.run.phi.stored_bricks() > 0);

    // The report: built once, its summary and JSON views say the same figures.
    const snvr::RunReport report = snvr::make_report(shell);
    const std::string summary = snvr::report_summary(report), json = snvr::report_json(report);
    CHECK(summary.find(snvr::grouped(shell.quality.triangles) + " triangles") != std::string::npos);
    CHECK(json.find("\"triangles\": " + std::to_string(shell.quality.triangles)) != std::string::npos);
    CHECK(summary.find("2 dropped") != std::string::npos);
    CHECK(json.find("\"dropped\": 2") != std::string::npos);

    // Each stage by its unit of work: the seconds over the units, beside the bytes at the least.
    const std::vector<snvr::StageUnit> units = snvr::stage_units(report);
    REQUIRE(units.size() == 6);
    const double band = double(shell.run.active_cells), triangles = double(shell.quality.triangles);
    CHECK(units[0].stage == "distance");
    CHECK(units[0].units == band);
    CHECK(units[0].ns == doctest::Approx(shell.run.seconds.distance / band * 1e9));
    CHECK(units[1].floor_bytes == double(shell.run.solver_bytes));  // the fields written once
    CHECK(units[2].units == band * double(shell.run.steps.size()));
    CHECK(units[2].floor_bytes == double(report.cycles.total) * double(shell.run.solver_bytes));
    CHECK(units[4].stage == "check");
    CHECK(units[4].units == triangles);
    CHECK(units[4].ns == doctest::Approx(shell.seconds.check / triangles * 1e9));
    CHECK(units[4].floor_bytes == 24.0 * double(shell.quality.vertices) + 12 * triangles);
    CHECK(units[3].floor_bytes == units[4].floor_bytes + 4 * band);  // the phase read, the mesh written
    CHECK(units[5].floor_bytes == 0);  // nothing written by the caller
    CHECK(summary.find("ns a band cell a step") != std::string::npos);
    CHECK(json.find("\"per_unit\"") != std::string::npos);
}

TEST_CASE("make_shell: units and scale take the points and every length to millimetres") {
    const snvr::PointSet points = snvr::shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03);
    snvr::ShellSettings cm = small();
    cm.params.offset = 0.05;
    cm.units = "cm";
    cm.scale = 2;
    const snvr::Shell scaled = snvr::make_shell(points, cm);
    // The same run on points and lengths scaled by hand: the same shell, bit for bit.
    snvr::PointCloud by_hand(points);
    by_hand.scale(20);
    snvr::ShellSettings mm = small();
    mm.params.offset = 0.05 * 20;
    const snvr::Shell plain = snvr::make_shell(std::move(by_hand), mm);
    CHECK(scaled.mesh.vertices == plain.mesh.vertices);
    CHECK(scaled.mesh.triangles == plain.mesh.triangles);
    CHECK(scaled.to_millimetres == 20);
    CHECK(scaled.run.offset == doctest::Approx(1.0));
    CHECK(scaled.warnings == plain.warnings);

    snvr::ShellSettings bad = small();
    bad.units = "furlong";
    CHECK_THROWS_WITH_AS(snvr::make_shell(points, bad), doctest::Contains("unit 'furlong'"), snvr::ParameterError);
    bad = small();
    bad.scale = 1e7;
    CHECK_THROWS_WITH_AS(snvr::make_shell(points, bad), doctest::Contains("1e-6 to 1e6"), snvr::ParameterError);
}

TEST_CASE("make_shell: the clusters it reports are the kept points' own count, taken over from the outlier rules") {
    using snvr::shapes::sphere;
    // One piece; two pieces far apart; a sphere with 5% random outliers; a blob beside a
    // sphere. Each with the outlier rules (the count taken over) and without.
    snvr::PointSet two = sphere({0.3, 0.5, 0.5}, 0.15, 0.02);
    for (const snvr::Vec3& p : sphere({0.8, 0.5, 0.5}, 0.12, 0.02)) two.push_back(p);
    snvr::PointSet blob = sphere({0.5, 0.5, 0.5}, 0.3, 0.03);
    for (const snvr::Vec3& p : sphere({0.95, 0.5, 0.5}, 0.04, 0.01)) blob.push_back(p);
    const snvr::PointSet clouds[] = {sphere({0.5, 0.5, 0.5}, 0.3, 0.03), two,
                                     snvr::shapes::with_outliers(snvr::shapes::noisy_sphere({0.5, 0.5, 0.5}, 0.3, 0.02, 0.002), 0.05),
                                     blob};
    std::size_t taken_over = 0;
    for (const snvr::PointSet& points : clouds) {
        for (bool drop : {true, false}) {
            snvr::ShellSettings s = small();
            s.params.resolution = 64;  // a link short of the gaps between the pieces
            s.drop_outliers = drop;
            const snvr::Shell shell = snvr::make_shell(points, s);
            std::vector<std::uint8_t> dropped(points.size(), 0);
            for (std::size_t i : shell.outliers.input_indices) dropped[i] = 1;
            snvr::PointSet kept;
            for (std::size_t i = 0; i < points.size(); ++i)
                if (!dropped[i]) kept.push_back(points[i]);
            CHECK(shell.clusters == snvr::count_point_clusters(snvr::PointCloud(kept), 2 * shell.run.offset));
            taken_over += shell.outliers.clusters != 0;
            if (!drop) CHECK(shell.outliers.clusters == 0);
        }
    }
    CHECK(taken_over == 4);
}

TEST_CASE("make_shell: centred on request, refusals named, and a callback that cancels") {
    snvr::PointSet far = snvr::shapes::sphere({500000.5, 4000000.5, 2.5}, 0.3, 0.03);
    // Far coordinates in float32 STL: refused as written, centred on request.
    snvr::ShellSettings kept = small();
    kept.origin = snvr::ShellOrigin::Keep;
    CHECK_THROWS_AS(snvr::make_shell(far, kept), snvr::IoError);
    snvr::ShellSettings centred = small();
    centred.origin = snvr::ShellOrigin::Centre;
    const snvr::Shell shell = snvr::make_shell(far, centred);
    CHECK(shell.shift[0] != 0);
    CHECK(!shell.shift_by_default);
    // Auto (the default): centred for STL as snvr-cl centres it, kept for an exact format.
    const snvr::Shell by_default = snvr::make_shell(far, small());
    CHECK(by_default.shift == shell.shift);
    CHECK(by_default.shift_by_default);
    CHECK(by_default.mesh.vertices == shell.mesh.vertices);
    snvr::ShellSettings exact = small();
    exact.written_as = ".obj";
    CHECK(snvr::make_shell(far, exact).shift == snvr::Vec3{0, 0, 0});
    const snvr::PointSet near = snvr::shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03);
    CHECK(!snvr::make_shell(near, small()).shift_by_default);
    CHECK(shell.quality.points_inside == far.size());

    const snvr::PointSet points = snvr::shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03);
    snvr::ShellSettings huge = small();
    huge.pieces.min_volume = 1e9;
    CHECK_THROWS_WITH_AS(snvr::make_shell(points, huge), doctest::Contains("(--min-piece-volume)"), snvr::Error);
    CHECK_THROWS_AS(snvr::make_shell(snvr::PointSet{}, small()), snvr::InputError);

    // Cancelled at each kind of stage: the stages seen stop there.
    for (const std::string stop : {"outliers", "domain", "distance", "init", "step", "mesh", "check"}) {
        CAPTURE(stop);
        std::string last;
        int seen = 0;
        const auto progress = [&](const snvr::Progress& p) {
            last = p.stage;
            ++seen;
            return !(p.stage == stop && (stop != "step" || p.step == 2));
        };
        CHECK_THROWS_AS(snvr::make_shell(points, small(), progress), snvr::Cancelled);
        CHECK(last == stop);
    }
    // And left alone, every stage is seen once (each step once); the mesh stage says its
    // parts as they begin, then what the depth guard did, as its outcome.
    std::string stages;
    std::vector<std::string> mesh_parts, outcomes;
    // A LiDAR-like scan with a thin wall: the depth guard lifts vertices.
    snvr::ShellSettings thin = small();
    thin.params.resolution = 64;
    thin.params.offset = 0.025;
    const snvr::PointSet scan = snvr::shapes::lidar_scan({0.5, 0.5, 0.5}, 0.7, 0.01, 0.04, 0.001);
    const snvr::Shell told = snvr::make_shell(scan, thin, [&](const snvr::Progress& p) {
        if (stages.empty() || stages.substr(stages.rfind(' ') + 1) != p.stage) stages += " " + p.stage;
        if (p.outcome) outcomes.push_back(p.stage + ": " + p.message);
        else if (p.stage == "mesh" && !p.message.empty()) mesh_parts.push_back(p.message);
        return true;
    });
    CHECK(stages == " outliers domain distance init step mesh check");
    REQUIRE(mesh_parts.size() >= 3);
    CHECK(mesh_parts[0] == "extracting the zero level set");
    CHECK(mesh_parts[1] == "fairing the surface");
    CHECK(mesh_parts[2] == "the depth guard: searching the points near the surface");
    REQUIRE(told.guard.moved_vertices > 0);
    REQUIRE(outcomes.size() == 1);
    CHECK(outcomes[0].rfind("mesh: " + snvr::grouped(told.guard.moved_vertices) + " vertices lifted along their normals", 0) == 0);
}

TEST_CASE("make_shell: mesh_ready is handed the finished mesh once, in the check stage, and what it throws is thrown") {
    const snvr::PointSet points = snvr::shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03);
    snvr::ShellSettings settings = small();
    int calls = 0;
    snvr::Mesh handed;
    bool in_check_stage = false;
    std::string stage;
    settings.mesh_ready = [&](const snvr::Mesh& mesh) {
        ++calls;
        handed = mesh;
        in_check_stage = stage == "check";  // the check has begun (its progress told), not ended
    };
    const snvr::Shell shell = snvr::make_shell(points, settings, [&](const snvr::Progress& p) {
        stage = p.stage;
        return true;
    });
    CHECK(calls == 1);
    CHECK(in_check_stage);
    CHECK(handed.vertices == shell.mesh.vertices);
    CHECK(handed.triangles == shell.mesh.triangles);
    CHECK(shell.seconds.mesh_ready >= 0);
    CHECK(shell.seconds.mesh_ready <= shell.seconds.total);
    settings.mesh_ready = [](const snvr::Mesh&) { throw snvr::IoError("cannot write 'x.stl': a test"); };
    CHECK_THROWS_WITH_AS(snvr::make_shell(points, settings), doctest::Contains("a test"), snvr::IoError);
}
