// The float point readers (read_float_points, issue 21): the origin rule and its bound,
// text split between threads at every possible place, records split between any number
// of threads, and one cloud read alike from every format.
#include <doctest/doctest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <zlib.h>

#include "io/point_readers.hpp"
#include "io/text_scan.hpp"
#include "snvr/error.hpp"
#include "snvr/point_io.hpp"
#include "temp_dir.hpp"
#include "test_files.hpp"

using snvr::PointSet;
using snvr::Vec3;
using snvr::detail::FloatPoints;
using snvr::detail::ParseOptions;
using snvr::testing::TempDir;
using snvr::testing::write_bytes;

namespace {

// Exact round trip text for a double.
std::string num(double v) {
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

// Appends v's bytes, little or big endian (the test hosts are little endian).
template <typename T>
void put(std::string& out, T v, bool big = false) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    if (big) std::reverse(bytes, bytes + sizeof(T));
    out.append(bytes, sizeof(T));
}

template <typename T>
void put_at(std::string& out, std::size_t at, T v) {
    std::memcpy(&out[at], &v, sizeof(T));
}

PointSet world(const FloatPoints& points) { return snvr::detail::world_points(points); }

double diagonal(const PointSet& points) {
    Vec3 lo = points[0], hi = points[0];
    for (const Vec3& p : points)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

// The promise of FloatPoints for points read from double values `exact`: each held point is
// exact - origin rounded to a float, and no point lies farther than 2.5 D from the origin.
void check_held(const FloatPoints& read, const PointSet& exact) {
    REQUIRE(read.xyz.size() == exact.size());
    const double d = diagonal(exact);
    std::size_t wrong = 0;
    double farthest = 0;
    for (std::size_t i = 0; i < exact.size(); ++i)
        for (int a = 0; a < 3; ++a) {
            const double offset = exact[i][a] - read.origin[a];
            wrong += read.xyz[i][a] != float(offset);
            farthest = std::max(farthest, std::abs(offset));
        }
    CHECK(wrong == 0);
    CHECK(farthest <= 2.5 * d);
}

// Points on a sphere of radius r about c, in a fixed pseudo-random order.
PointSet sphere(std::size_t n, const Vec3& c, double r, unsigned seed = 7) {
    std::mt19937_64 g(seed);
    std::normal_distribution<double> normal;
    PointSet points;
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 v{normal(g), normal(g), normal(g)};
        const double len = std::hypot(v[0], v[1], v[2]);
        points.push_back({c[0] + r * v[0] / len, c[1] + r * v[1] / len, c[2] + r * v[2] / len});
    }
    return points;
}

// Coordinates on a grid of 1/1024: exact in floats, in short decimals and in LAS integers.
PointSet on_grid(PointSet points) {
    for (Vec3& p : points)
        for (double& x : p) x = std::round(x * 1024) / 1024;
    return points;
}

std::string xyz_text(const PointSet& points, const char* separator = " ", const char* end = "\n") {
    std::string text;
    for (const Vec3& p : points) text += num(p[0]) + separator + num(p[1]) + separator + num(p[2]) + end;
    return text;
}

std::string binary_ply(const PointSet& points, bool big, bool doubles) {
    std::string bytes = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\nelement vertex " + std::to_string(points.size()) + "\nproperty uchar flag\n";
    for (const char* axis : {"x", "y", "z"}) bytes += std::string("property ") + (doubles ? "double " : "float ") + axis + "\n";
    bytes += "property float nx\nend_header\n";
    for (const Vec3& p : points) {
        put<std::uint8_t>(bytes, 1);
        for (double x : p) doubles ? put<double>(bytes, x, big) : put<float>(bytes, float(x), big);
        put<float>(bytes, 0.5f, big);
    }
    return bytes;
}

// LAS 1.2 format 1 (28-byte records) with the given scale, offset and header box.
std::string las(const PointSet& points, double scale, const Vec3& offset, const Vec3& lo, const Vec3& hi) {
    std::string s(227, '\0');
    s.replace(0, 4, "LASF");
    s[24] = 1;
    s[25] = 2;
    put_at<std::uint16_t>(s, 94, 227);
    put_at<std::uint32_t>(s, 96, 227);
    s[104] = 1;
    put_at<std::uint16_t>(s, 105, 28);
    put_at<std::uint32_t>(s, 107, std::uint32_t(points.size()));
    for (int a = 0; a < 3; ++a) {
        put_at<double>(s, 131 + 8 * std::size_t(a), scale);
        put_at<double>(s, 155 + 8 * std::size_t(a), offset[a]);
        put_at<double>(s, 179 + 16 * std::size_t(a), hi[a]);
        put_at<double>(s, 187 + 16 * std::size_t(a), lo[a]);
    }
    for (const Vec3& p : points) {
        std::string record(28, '\x5a');
        for (int a = 0; a < 3; ++a)
            put_at<std::int32_t>(record, 4 * std::size_t(a), std::int32_t(std::lround((p[a] - offset[a]) / scale)));
        s += record;
    }
    return s;
}

// The message parse_points throws for `data` read as `name`, or "" when it reads.
std::string failure(const std::string& data, const std::string& name, const ParseOptions& options) {
    try {
        snvr::detail::parse_points(data, name, options);
    } catch (const snvr::InputError& e) {
        return e.what();
    }
    return "";
}

// Serial: one block, one thread.
ParseOptions serial() {
    ParseOptions o;
    o.text_block = std::size_t(1) << 40;
    o.threads = 1;
    return o;
}

ParseOptions split(std::size_t block, int threads) {
    ParseOptions o;
    o.text_block = block;
    o.threads = threads;
    return o;
}

bool same(const FloatPoints& a, const FloatPoints& b) { return a.origin == b.origin && a.xyz == b.xyz; }

}  // namespace

TEST_CASE("parse_number: std::from_chars with what the readers have always accepted") {
    const auto value = [](const char* text) {
        double v = -12345;
        return snvr::detail::parse_number(text, v) ? v : -12345;
    };
    CHECK(value("+1.5") == 1.5);  // a leading '+', which from_chars alone refuses
    CHECK(value("-2.5e-3") == -2.5e-3);
    CHECK(value("7") == 7);
    CHECK(value(".5") == 0.5);
    CHECK(value("5.") == 5);
    CHECK(std::signbit(value("-0")));
    CHECK(value("1e-400") == 0);                  // below a double's range: 0, not an error
    CHECK(value("1e400") == HUGE_VAL);            // above it: infinity, refused later as non-finite
    CHECK(value("-1e400") == -HUGE_VAL);
    CHECK(value("4.9e-324") == 4.9e-324);         // the least subnormal, rounded as strtod would
    CHECK(value("2.2250738585072011e-308") == 2.2250738585072011e-308);
    CHECK(value("inf") == HUGE_VAL);
    CHECK(value("-Infinity") == -HUGE_VAL);
    CHECK(std::isnan(value("nan")));
    CHECK(std::isnan(value("NaN")));
    CHECK(value("0.1") == 0.1);                   // correctly rounded
    CHECK(value("123456.78901234567") == 123456.78901234567);
    for (const char* refused : {"", "+", "-", "++1", "+-1", "--1", "1e", "1.5x", "0x10", "1,5", " 1", "1 ", "e5", "."}) {
        CAPTURE(refused);
        CHECK(value(refused) == -12345);
    }
}

TEST_CASE("origin: float files held exactly about 0, wherever they lie") {
    TempDir dir("read-points");
    // A float32 PLY of survey coordinates: floats already, so nothing is shifted or rounded.
    const PointSet far = sphere(300, {500000, 4000000, 120}, 40);
    const std::string path = dir.file("far.ply");
    write_bytes(path, binary_ply(far, false, false));
    const FloatPoints read = snvr::detail::read_float_points(path);
    CHECK(read.origin == Vec3{0, 0, 0});
    REQUIRE(read.xyz.size() == far.size());
    for (std::size_t i = 0; i < far.size(); ++i)
        for (int a = 0; a < 3; ++a) CHECK(read.xyz[i][a] == float(far[i][a]));
    // A bundled scan (float32 PLY): the same floats as the file, through read_points too.
    const std::string bunny = std::string(SNVR_DATA_DIR) + "/bunny.ply";
    const FloatPoints scan = snvr::detail::read_float_points(bunny);
    CHECK(scan.origin == Vec3{0, 0, 0});
    const PointSet doubles = snvr::read_points(bunny);
    REQUIRE(doubles.size() == scan.xyz.size());
    bool equal = true;
    for (std::size_t i = 0; i < doubles.size(); ++i)
        for (int a = 0; a < 3; ++a) equal = equal && doubles[i][a] == double(scan.xyz[i][a]);
    CHECK(equal);
}

TEST_CASE("origin: double values near 0 about 0, far ones about a round point, within the bound") {
    TempDir dir("read-points");
    const PointSet near = sphere(500, {0.2, -0.1, 0.3}, 1);
    write_bytes(dir.file("near.xyz"), xyz_text(near));
    const FloatPoints held = snvr::detail::read_float_points(dir.file("near.xyz"));
    CHECK(held.origin == Vec3{0, 0, 0});
    check_held(held, near);

    // Survey coordinates in text and in double PLY: a round origin in the box, the error
    // only the floats' rounding of x - origin (which floats of x itself would not be).
    const PointSet survey = sphere(5000, {500003.7, 4000001.2, 13.1}, 3.5);
    write_bytes(dir.file("survey.xyz"), xyz_text(survey));
    write_bytes(dir.file("survey.ply"), binary_ply(survey, true, true));
    for (const char* name : {"survey.xyz", "survey.ply"}) {
        CAPTURE(name);
        const FloatPoints read = snvr::detail::read_float_points(dir.file(name));
        CHECK(read.origin == Vec3{500004, 4000001, 13});  // the first 4096 points' box, to metres
        check_held(read, survey);
        const PointSet back = snvr::read_points(dir.file(name));
        double worst = 0;
        for (std::size_t i = 0; i < survey.size(); ++i)
            for (int a = 0; a < 3; ++a) worst = std::max(worst, std::abs(back[i][a] - survey[i][a]));
        CHECK(worst <= 4 * std::ldexp(1.0, -24));  // |x - origin| is under 4 here
        CHECK(worst > 0);
    }

    // The origin comes from the first points only: one far corner first, then a cloud across
    // a wider box. Within 2.5 diagonals still, however few points choose it.
    PointSet spread = sphere(2000, {7000.25, -3000.5, 42}, 0.01, 1);
    const PointSet rest = sphere(3000, {7050, -3080, 60}, 90, 2);
    spread.insert(spread.end(), rest.begin(), rest.end());
    const std::string text = xyz_text(spread);
    for (std::size_t sample : {std::size_t(1), std::size_t(10), std::size_t(4096)}) {
        CAPTURE(sample);
        ParseOptions options;
        options.origin_sample = sample;
        const FloatPoints read = snvr::detail::parse_points(text, "spread.xyz", options);
        CHECK(read.origin != Vec3{0, 0, 0});
        check_held(read, spread);
    }
    // A near first sample keeps origin 0 even when later points lie far: still within the bound.
    PointSet near_first = sphere(100, {0, 0, 0}, 1, 3);
    const PointSet far_later = sphere(100, {30, 20, 10}, 1, 4);
    near_first.insert(near_first.end(), far_later.begin(), far_later.end());
    ParseOptions first_hundred;
    first_hundred.origin_sample = 100;
    const FloatPoints read = snvr::detail::parse_points(xyz_text(near_first), "mixed.xyz", first_hundred);
    CHECK(read.origin == Vec3{0, 0, 0});
    check_held(read, near_first);
    // One point far away: itself, exactly.
    const FloatPoints one = snvr::detail::parse_points("123456.789 -9876543.21 0.125\n", "one.xyz");
    CHECK(one.origin == Vec3{123456.789, -9876543.21, 0.125});
    CHECK(world(one) == PointSet{{123456.789, -9876543.21, 0.125}});
}

TEST_CASE("origin: LAS takes its header's box, unless the points lie outside it") {
    TempDir dir("read-points");
    const PointSet scan = on_grid(sphere(3000, {500010, 4000020, 30}, 8));
    const double scale = 1.0 / 1024;
    const Vec3 offset{500000, 4000000, 0};
    // The true box: its round centre (the box is 16 across: steps of 10).
    write_bytes(dir.file("true.las"), las(scan, scale, offset, {500002, 4000012, 22}, {500018, 4000028, 38}));
    const FloatPoints read = snvr::detail::read_float_points(dir.file("true.las"));
    CHECK(read.origin == Vec3{500010, 4000020, 30});
    CHECK(world(read) == scan);  // on a grid of 1/1024 near the origin: exact
    // A header box far off, one of no size, one of NaN: the first points choose instead.
    for (const auto& [lo, hi] : {std::pair<Vec3, Vec3>{{0, 0, 0}, {1, 1, 1}},
                                 {{-1e9, -1e9, -1e9}, {1e9, 1e9, 1e9}},
                                 {{500010, 4000020, 30}, {500010, 4000020, 30}},
                                 {{NAN, 0, 0}, {1, 1, 1}}}) {
        CAPTURE(lo[0]);
        write_bytes(dir.file("lies.las"), las(scan, scale, offset, lo, hi));
        const FloatPoints held = snvr::detail::read_float_points(dir.file("lies.las"));
        check_held(held, scan);
        CHECK(world(held) == scan);
    }
}

TEST_CASE("origin: a point floats cannot hold about the origin is refused by number") {
    const std::string span = "0 0 0\n1 1 1\n1e308 0 0\n-1e308 0 0\n";
    const std::string message = failure(span, "span.xyz", {});
    CHECK(message.find("span.xyz: point 2 (1e+308 0 0) lies beyond 32-bit float range") != std::string::npos);
    CHECK(failure("0 0 0\n1 nan 0\n", "nan.xyz", {}).find("point 1 has a non-finite coordinate (1 nan 0)") !=
          std::string::npos);
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
                      "property double z\nend_header\n";
    for (double x : {0.0, 0.0, 0.0, 1e300, 0.0, 0.0}) put<double>(ply, x);
    CHECK(failure(ply, "far.ply", {}).find("far.ply: point 1 (1e+300 0 0) lies beyond") != std::string::npos);
}

namespace {

// A text in which lines of every length, blank lines, comments and CRLF ends fall on
// every byte a block could start at.
std::string ragged_xyz() {
    std::string text = "\xEF\xBB\xBFX;Y;Z;I\r\n";  // a BOM and a header of names
    const PointSet points = sphere(60, {3, -2, 1}, 2.5, 11);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& p = points[i];
        if (i % 7 == 3) text += "\r\n";
        if (i % 11 == 5) text += "# a comment; 1 2 3\n";
        if (i % 13 == 2) text += "42\n";  // a PTS point count
        if (i % 3 == 0) text += num(p[0]) + " " + num(p[1]) + "\t" + num(p[2]) + "\n";
        else if (i % 3 == 1) text += num(p[0]) + "," + num(p[1]) + "," + num(p[2]) + ",255,0,0\r\n";
        else {
            std::string line = num(p[0]) + ";" + num(p[1]) + ";" + num(p[2]) + ";17\n";
            std::replace(line.begin(), line.end(), '.', ',');
            text += line;
        }
    }
    return text;
}

std::string ragged_ply() {
    std::string text = "ply\nformat ascii 1.0\nelement camera 2\nproperty float f\nelement vertex 50\n"
                       "property double x\nproperty list uchar int idx\nproperty float y\nproperty float z\n"
                       "element face 2\nproperty list uchar int vertex_indices\nend_header\n1.5\n\n2.5\n";
    const PointSet points = sphere(50, {0, 0, 0}, 1, 12);
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (i % 9 == 4) text += "  \n";
        text += num(points[i][0]) + " " + std::to_string(i % 4);
        for (std::size_t k = 0; k < i % 4; ++k) text += " " + std::to_string(k);
        text += " " + num(points[i][1]) + " " + num(points[i][2]) + "\n";
    }
    return text + "3 0 1 2\n3 1 2 3\n";
}

// ASCII PLY whose vertex `bad` is no number (its line number in `line`), with vertex 0
// non-finite, blank lines about, an element before the vertices and one after.
std::string ply_with_bad_vertex(std::size_t bad, std::size_t& line) {
    std::string text = "ply\nformat ascii 1.0\nelement camera 2\nproperty float f\nelement vertex 50\n"
                       "property double x\nproperty list uchar int idx\nproperty float y\nproperty float z\n"
                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n1.5\n\n2.5\n";
    std::size_t lines = 15;
    for (std::size_t i = 0; i < 50; ++i) {
        if (i % 4 == 2) {
            text += "\n";
            ++lines;
        }
        text += i == bad ? "1 0 nope 2\n" : i == 0 ? "nan 0 1 1\n" : std::to_string(i) + " 1 7 0.5 -0.25\n";
        if (i == bad) line = lines + 1;
        ++lines;
    }
    return text + "3 0 1 2\n";
}

std::string ragged_off() {
    std::string text = "# shape\nCOFF\n\n40 2 0\n";
    const PointSet points = sphere(40, {0, 0, 0}, 1, 13);
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (i % 6 == 1) text += "# a vertex comment\n";
        text += num(points[i][0]) + " " + num(points[i][1]) + " " + num(points[i][2]) + " 255 0 0 255\n";
    }
    return text + "3 0 1 2\n3 2 1 3\n";
}

std::string ragged_obj() {
    std::string text = "mtllib a.mtl\n";
    const PointSet points = sphere(40, {0, 0, 0}, 1, 14);
    for (std::size_t i = 0; i < points.size(); ++i) {
        text += "v " + num(points[i][0]) + " " + num(points[i][1]) + " " + num(points[i][2]) + "\n";
        if (i % 5 == 0) text += "vn 0 0 1\nvt 0.5 0.5\n";
    }
    return text + "f 1 2 3\n";
}

}  // namespace

TEST_CASE("text split between threads: the same points whatever the blocks and threads") {
    std::string cr_only;  // old Mac line ends: "\r" alone
    for (char c : ragged_xyz())
        if (c != '\r') cr_only += c == '\n' ? '\r' : c;
    const std::vector<std::pair<std::string, std::string>> files = {
        {"a.xyz", ragged_xyz()}, {"b.csv", cr_only}, {"c.ply", ragged_ply()}, {"d.off", ragged_off()}, {"e.obj", ragged_obj()}};
    for (const auto& [name, text] : files) {
        CAPTURE(name);
        const FloatPoints reference = snvr::detail::parse_points(text, name, serial());
        CHECK(reference.xyz.size() >= 40);
        std::size_t differ = 0;
        for (std::size_t block = 1; block <= text.size() + 1; ++block)
            for (int threads : {1, 2, 3}) differ += !same(snvr::detail::parse_points(text, name, split(block, threads)), reference);
        CHECK(differ == 0);
    }
}

TEST_CASE("text split between threads: an error names its line and vertex, from any block") {
    // A bad line at every place in turn: the message a serial reader gives, from every split.
    const std::string good = ragged_xyz();
    std::vector<std::size_t> starts;  // every line's first byte, after the header line
    for (std::size_t at = good.find('\n') + 1; at < good.size(); at = good.find('\n', at) + 1) starts.push_back(at);
    std::size_t checked = 0, differ = 0;
    for (std::size_t k = 0; k < starts.size(); k += 3) {
        std::string bad = good;
        bad.insert(starts[k], "1 2 oops\n");
        const std::size_t line = std::size_t(std::count(bad.begin(), bad.begin() + std::ptrdiff_t(starts[k]), '\n')) + 1;
        const std::string expected = "bad.xyz: line " + std::to_string(line) + ": expected a number, found 'oops'";
        CHECK(failure(bad, "bad.xyz", serial()) == expected);
        for (std::size_t block : {std::size_t(1), std::size_t(7), std::size_t(64), std::size_t(333)})
            for (int threads : {2, 3}) {
                differ += failure(bad, "bad.xyz", split(block, threads)) != expected;
                ++checked;
            }
    }
    CHECK(checked > 100);
    CHECK(differ == 0);

    // PLY: the vertex counted in the element, the line in the file; a non-finite vertex
    // before it waits (a serial reader meets the bad line first, then checks the values).
    for (std::size_t bad : {std::size_t(0), std::size_t(17), std::size_t(49)}) {
        CAPTURE(bad);
        std::size_t line = 0;
        const std::string text = ply_with_bad_vertex(bad, line);
        const std::string expected = "v.ply: line " + std::to_string(line) + ": vertex " + std::to_string(bad) +
                                     ": expected a number for 'y', found 'nope'";
        CHECK(failure(text, "v.ply", serial()) == expected);
        std::size_t wrong = 0;
        for (std::size_t block = 1; block < text.size(); block += 5)
            for (int threads : {2, 3}) wrong += failure(text, "v.ply", split(block, threads)) != expected;
        CHECK(wrong == 0);
    }
    const std::string ply = ragged_ply();
    // Too few vertices: counted across every block.
    std::string short_ply = ply;
    short_ply.replace(short_ply.find("element vertex 50"), 17, "element vertex 99");
    short_ply.resize(short_ply.rfind("3 0 1 2\n"));
    const std::string ends = failure(short_ply, "s.ply", serial());
    CHECK(ends.find("expected 99 vertices, file ends after 50 (line ") != std::string::npos);
    for (std::size_t block = 1; block < short_ply.size(); block += 17) CHECK(failure(short_ply, "s.ply", split(block, 3)) == ends);
}

TEST_CASE("big files: blocks and thread shares meet without losing or doubling a point") {
    // About 3 MB of text: several default blocks of 1 MB, each cut mid-line.
    const PointSet cloud = sphere(90000, {0.5, 0.5, 0.5}, 0.5, 21);
    const std::string text = xyz_text(cloud);
    REQUIRE(text.size() > 3 * (std::size_t(1) << 20));
    const FloatPoints reference = snvr::detail::parse_points(text, "big.xyz", serial());
    REQUIRE(reference.xyz.size() == cloud.size());
    check_held(reference, cloud);
    for (int threads : {0, 2, 3}) {
        ParseOptions options;
        options.threads = threads;
        CHECK(same(snvr::detail::parse_points(text, "big.xyz", options), reference));
    }
    // Records split evenly among 1 to 7 threads: counts that do not divide.
    for (bool doubles : {false, true}) {
        const std::string ply = binary_ply(cloud, !doubles, doubles);
        ParseOptions one;
        one.threads = 1;
        const FloatPoints first = snvr::detail::parse_points(ply, "big.ply", one);
        if (doubles) check_held(first, cloud);
        for (int threads = 2; threads <= 7; ++threads) {
            ParseOptions options;
            options.threads = threads;
            CHECK(same(snvr::detail::parse_points(ply, "big.ply", options), first));
        }
    }
}

TEST_CASE("records read from the file part by part: the same points whatever the part and threads") {
    TempDir dir("read-parts");
    // Enough records for the threads to share them (kParallelCheapItems); far: an origin is chosen.
    const PointSet cloud = sphere(70001, {1000, -2000, 300}, 1.5, 41);
    std::string long_header = binary_ply(cloud, false, true);  // a header beyond the first 64 KiB read
    for (int i = 0; i < 5000; ++i) long_header.insert(long_header.find("element"), "comment padding the header\n");
    std::string faces_first = binary_ply(cloud, false, false);  // a list before the vertices: read whole
    faces_first.insert(faces_first.find("element vertex"), "element face 2\nproperty list uchar int vertex_indices\n");
    std::string face_bytes;
    for (int f = 0; f < 2; ++f) {
        put<std::uint8_t>(face_bytes, 3);
        for (int v = 0; v < 3; ++v) put<std::int32_t>(face_bytes, v);
    }
    faces_first.insert(faces_first.find("end_header\n") + 11, face_bytes);
    const std::vector<std::pair<std::string, std::string>> files = {
        {"f.ply", binary_ply(cloud, false, false)}, {"d.ply", binary_ply(cloud, true, true)},
        {"l.las", las(cloud, 1e-6, {1000, -2000, 300}, {998, -2002, 298}, {1002, -1998, 302})},
        {"h.ply", long_header}, {"g.ply", faces_first}};
    for (const auto& [name, bytes] : files) {
        CAPTURE(name);
        const std::string path = dir.file(name);
        snvr::testing::write_bytes(path, bytes);
        const FloatPoints reference = snvr::detail::parse_points(bytes, name, serial());  // from memory
        REQUIRE(reference.xyz.size() == cloud.size());
        std::size_t differ = 0;
        for (std::size_t part : {std::size_t(1), std::size_t(27), std::size_t(1000), std::size_t(1) << 20})
            for (int threads : {1, 2, 3}) {
                ParseOptions options;
                options.read_part = part;
                options.threads = threads;
                differ += !same(snvr::detail::read_float_points(path, options), reference);
            }
        CHECK(differ == 0);
    }
}

TEST_CASE("one cloud, every format: the same points") {
    TempDir dir("read-points");
    // On a grid of 1/1024, so that every format holds the values exactly, near 0 and far.
    for (const Vec3& centre : {Vec3{0, 0, 0}, Vec3{1000, -2000, 300}}) {
        CAPTURE(centre[0]);
        const PointSet cloud = on_grid(sphere(5000, centre, 1.5, 31));
        std::string ascii = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(cloud.size()) +
                            "\nproperty float x\nproperty float y\nproperty float z\nend_header\n" + xyz_text(cloud);
        std::string semicolons = xyz_text(cloud, ";", ";0\r\n");
        std::replace(semicolons.begin(), semicolons.end(), '.', ',');
        std::string obj, off = "OFF\n" + std::to_string(cloud.size()) + " 0 0\n" + xyz_text(cloud);
        for (const Vec3& p : cloud) obj += "v " + num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + "\n";
        const Vec3 lo{centre[0] - 2, centre[1] - 2, centre[2] - 2}, hi{centre[0] + 2, centre[1] + 2, centre[2] + 2};
        const std::vector<std::pair<std::string, std::string>> files = {
            {"a.ply", ascii},
            {"le.ply", binary_ply(cloud, false, false)},
            {"be.ply", binary_ply(cloud, true, false)},
            {"le64.ply", binary_ply(cloud, false, true)},
            {"be64.ply", binary_ply(cloud, true, true)},
            {"p.xyz", xyz_text(cloud)},
            {"p.pts", std::to_string(cloud.size()) + "\n" + xyz_text(cloud, " ", " 0 255 255 255\n")},
            {"p.csv", "x,y,z\n" + xyz_text(cloud, ",")},
            {"p.txt", "\xEF\xBB\xBF//X;Y;Z;I\r\n" + semicolons},
            {"p.obj", obj},
            {"p.off", off},
            {"p.las", las(cloud, 1.0 / 1024, centre, lo, hi)},
            {"p.xyz.gz", snvr::testing::gzip(xyz_text(cloud))},
            {"be64.ply.gz", snvr::testing::gzip(binary_ply(cloud, true, true))}};
        for (const auto& [name, bytes] : files) {
            CAPTURE(name);
            write_bytes(dir.file(name), bytes);
            CHECK(snvr::read_points(dir.file(name)) == cloud);
        }
    }
}
