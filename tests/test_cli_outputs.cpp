// What a printer user gets from snvr-cl: 3MF, lengths in millimetres whatever the
// input's unit, and a report a script can read.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <png.h>

#include <cmath>
#include <string>

#include "cli_run.hpp"
#include "snvr/point_io.hpp"

namespace fs = std::filesystem;
using namespace cli_testing;

namespace {

// Points on a sphere of radius r (in the file's units) around the origin.
std::string sphere_xyz(double r) {
    std::string text;
    char line[120];
    for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 48; ++j) {
            const double th = M_PI * (i + 0.5) / 24, ph = M_PI * j / 24;
            std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", r * std::sin(th) * std::cos(ph),
                          r * std::sin(th) * std::sin(ph), r * std::cos(th));
            text += line;
        }
    return text;
}

// 1234567 -> "1,234,567", as the summary prints counts.
std::string grouped_digits(std::size_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

nlohmann::json read_json(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("--units and --scale: every output in millimetres, the size in the summary") {
    TempDir t;
    // A sphere of radius 0.05 m: a shell about 100 mm across (plus the wall).
    const std::string input = t.file("ball.xyz", sphere_xyz(0.05));
    Run r = run("reconstruct " + input + " -o " + t.out() + " --resolution 48 --units m");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("(lengths in m times 1000)") != std::string::npos);
    CHECK(r.output.find("size             11") != std::string::npos);  // 100 mm and the wall
    CHECK(r.output.find("mm across") == std::string::npos);           // no small-shell warning
    // The same file in mm is 0.1 mm across: the summary says so, and a warning asks for --units.
    fs::remove(t.out());
    r = run("reconstruct " + input + " -o " + t.out() + " --resolution 48");
    CHECK(r.code == 0);
    CHECK(r.output.find("warning: the shell is only 0.1") != std::string::npos);
    CHECK(r.output.find("give --units") != std::string::npos);
    // Inches at 1:2 with a given offset (in inches too): 0.05 in x 2 x 25.4 = 2.54 mm.
    fs::remove(t.out());
    r = run("reconstruct " + input + " -o " + t.out() + " --resolution 48 --units in --scale 2 --offset 0.005");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("offset           0.254 ") != std::string::npos);
    CHECK(r.output.find("(lengths in in times 50.8)") != std::string::npos);
    fs::remove(t.out());
    expect_failure("reconstruct " + input + " -o " + t.out() + " --units furlong", 2, "mm, cm, m or in", t);
    expect_failure("reconstruct " + input + " -o " + t.out() + " --scale -1", 2, "--scale", t);
}

TEST_CASE("3MF output and a JSON report, written with the mesh or not at all") {
    TempDir t;
    const std::string input = t.file("ball.xyz", sphere_xyz(30));  // mm
    const fs::path mesh = t.path / "ball.3mf", report = t.path / "ball.json", volume = t.path / "ball.nrrd";
    const Run r = run("reconstruct " + input + " -o " + mesh.string() + " --resolution 48 --volume " +
                      volume.string() + " --report " + report.string());
    CAPTURE(r.output);
    REQUIRE(r.code == 0);
    const nlohmann::json j = read_json(report);
    CHECK(j["units"] == "mm");
    CHECK(j["outputs"][0]["path"] == mesh.string());
    CHECK(j["outputs"][0]["bytes"] == fs::file_size(mesh));
    CHECK(j["outputs"][1]["bytes"] == fs::file_size(volume));
    CHECK(j["mesh"]["closed"] == true);
    CHECK(j["mesh"]["manifold"] == true);
    CHECK(j["mesh"]["oriented"] == true);
    CHECK(j["mesh"]["zero_area_triangles"] == 0);
    CHECK(j["check"]["points_inside"] == 24 * 48);
    CHECK(j["check"]["wall_p01_2l"].get<double>() > 0.5);
    CHECK(j["grid"]["nx"].get<int>() >= 48);
    CHECK(j["offset"]["why"].get<std::string>().find("voxels") != std::string::npos);
    CHECK(j["seconds"]["total"].get<double>() >= j["seconds"]["steps"].get<double>());
    CHECK(j["size"][0].get<double>() > 60);
    CHECK(j["warnings"].empty());
    CHECK(j["v_cycles"]["total"].get<int>() >= int(j["flow"]["steps"].get<std::size_t>()));
    // The summary's triangle count is the file's (3MF read back: test_io).
    CHECK(r.output.find(grouped_digits(j["mesh"]["triangles"].get<std::size_t>())) != std::string::npos);
    // A report that cannot be written: neither the mesh nor the report appears.
    fs::remove(mesh);
    const std::string nowhere = (t.path / "missing" / "r.json").string();
    const Run bad = run("reconstruct " + input + " -o " + mesh.string() + " --resolution 48 --report " + nowhere);
    CHECK(bad.code == 1);
    CHECK(!fs::exists(mesh));
    expect_failure("reconstruct " + input + " -o " + t.out() + " --report r.txt", 2, ".json", t);
}

TEST_CASE("sample --random: N points at random on the surface, by seed") {
    TempDir t;
    const std::string a = (t.path / "a.xyz").string(), b = (t.path / "b.xyz").string();
    REQUIRE(run("sample torus --random 700 --seed 3 -o " + a).code == 0);
    REQUIRE(run("sample torus --random 700 --seed 3 -o " + b).code == 0);
    CHECK(snvr::read_points(a).size() == 700);
    CHECK(snvr::read_points(a) == snvr::read_points(b));
    expect_failure("sample torus --random 700 --spacing 0.01 -o " + a, 2, "--random", t);
}

TEST_CASE("outliers: dropped by default, written where asked, kept on request") {
    TempDir t;
    // The sampler's sphere with 5% random points in its box (the paper's Fig. 10).
    const std::string points = (t.path / "noisy.ply").string();
    REQUIRE(run("sample sphere --spacing 0.01 --outliers 0.05 -o " + points).code == 0);
    const std::string dropped = (t.path / "dropped.xyz").string();
    Run r = run("reconstruct " + points + " -o " + t.out() + " --resolution 96 --outliers " + dropped);
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("2 components") != std::string::npos);
    CHECK(r.output.find("written to " + dropped) != std::string::npos);
    std::ifstream in(dropped);
    std::size_t lines = 0;
    for (std::string line; std::getline(in, line);) ++lines;
    CHECK(lines > 385);  // most of the 770
    CHECK(r.output.find("outliers         " + std::to_string(lines) + " dropped") != std::string::npos);
    fs::remove(t.out());
    r = run("reconstruct " + points + " -o " + t.out() + " --resolution 96 --keep-outliers");
    CHECK(r.code == 0);
    CHECK(r.output.find("outliers         ") == std::string::npos);
    CHECK(r.output.find("2 components") == std::string::npos);  // beads and bubbles
    fs::remove(t.out());
    expect_failure("reconstruct " + points + " -o " + t.out() + " --keep-outliers --outliers " + dropped, 2,
                   "exclude each other", t);
}

TEST_CASE("pieces: --keep-largest and --min-piece-volume drop floating debris, counted in the summary") {
    TempDir t;
    // A ball of radius 30 mm and two clusters of 20 and 30 points far from it.
    std::string text = sphere_xyz(30);
    char line[80];
    for (int k = 0; k < 20; ++k) {
        std::snprintf(line, sizeof line, "%g %g 0\n", 60 + 0.3 * (k % 5), 0.3 * (k / 5));
        text += line;
    }
    for (int k = 0; k < 30; ++k) {
        std::snprintf(line, sizeof line, "%g %g 5\n", -60 + 0.5 * (k % 6), 0.5 * (k / 6));
        text += line;
    }
    const std::string input = t.file("debris.xyz", text);
    Run r = run("reconstruct " + input + " -o " + t.out() + " --resolution 96");
    CAPTURE(r.output);
    CHECK(r.output.find("3 solid pieces") != std::string::npos);
    fs::remove(t.out());
    r = run("reconstruct " + input + " -o " + t.out() + " --resolution 96 --keep-largest 1");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("1 solid piece (the other components bound cavities); 2 dropped") != std::string::npos);
    CHECK(r.output.find("of " + std::to_string(24 * 48 + 50) + " points (2 pieces dropped on request)") !=
          std::string::npos);
    fs::remove(t.out());
    // The clusters' beads are a few hundred mm^3; the ball tens of thousands.
    r = run("reconstruct " + input + " -o " + t.out() + " --resolution 96 --min-piece-volume 5000");
    CHECK(r.output.find("1 solid piece (the other components bound cavities); 2 dropped") != std::string::npos);
    fs::remove(t.out());
    expect_failure("reconstruct " + input + " -o " + t.out() + " --keep-largest -2", 2, "a count", t);
}

TEST_CASE("a mesh as input: its triangles thickened, not only its corners") {
    TempDir t;
    // A shell from points, then that shell's STL thickened in turn.
    const std::string points = t.file("ball.xyz", sphere_xyz(30));
    const std::string first = (t.path / "first.stl").string();
    REQUIRE(run("reconstruct " + points + " -o " + first + " --resolution 48 --quiet").code == 0);
    const Run r = run("reconstruct " + first + " -o " + t.out() + " --resolution 48");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("read: a mesh of ") != std::string::npos);
    CHECK(r.output.find(" triangles, sampled at ") != std::string::npos);
    CHECK(r.output.find("closed yes, manifold yes, oriented yes") != std::string::npos);
    CHECK(r.output.find("1 solid piece") != std::string::npos);
}

TEST_CASE("--preview: the shell shaded beside a cut through it") {
    TempDir t;
    const std::string input = t.file("ball.xyz", sphere_xyz(30));
    const std::string preview = (t.path / "ball.png").string();
    const Run r = run("reconstruct " + input + " -o " + t.out() + " --resolution 64 --preview " + preview);
    CAPTURE(r.output);
    REQUIRE(r.code == 0);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&image, preview.c_str()));
    image.format = PNG_FORMAT_RGB;
    std::vector<unsigned char> rgb(PNG_IMAGE_SIZE(image));
    REQUIRE(png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr));
    CHECK(image.width == 1604);
    CHECK(image.height == 800);
    const auto red = [&](int x, int y) { return int(rgb[(std::size_t(y) * image.width + std::size_t(x)) * 3]); };
    // Left: the ball shaded (grey) at the middle, white in the corner.
    CHECK(red(400, 400) < 250);
    CHECK(red(5, 5) == 255);
    // Right: the cut is a ring: hollow (white) in the middle, dark where the wall is.
    // The box is about 2 x 34 mm across 800 pixels: the wall (30 +- 2.5 mm) near 343-380 px out.
    const int cx = 804 + 400;
    CHECK(red(cx, 400) == 255);
    bool wall = false;
    for (int dx = 330; dx < 395; ++dx) wall = wall || red(cx + dx, 400) < 100;
    CHECK(wall);
    fs::remove(t.out());
    expect_failure("reconstruct " + input + " -o " + t.out() + " --preview p.jpg", 2, ".png", t);
}
