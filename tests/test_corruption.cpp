// A corruption campaign: generated mutations of every input format (bytes flipped,
// inserted, deleted, duplicated, cut short, numbers made absurd; and, one in four, a
// header field made absurd knowing the format: counts, offsets, record sizes, scales,
// gzip's trailer), each run through snvr-cl with a small reconstruction. None may crash
// or hang; every failure is exit 1 with one error naming the file, and leaves no output
// and no temporary.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bounded_run.hpp"
#include "temp_dir.hpp"
#include "test_files.hpp"

namespace fs = std::filesystem;

namespace {

constexpr int kMutationsPerFormat = 200;
constexpr double kTimeLimit = 30;  // seconds a run may take (a healthy one takes a tenth)

std::vector<std::array<double, 3>> sphere(int rings) {
    std::vector<std::array<double, 3>> p;
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < 2 * rings; ++j) {
            const double th = M_PI * (i + 0.5) / rings, ph = M_PI * j / rings;
            p.push_back({0.3 * std::sin(th) * std::cos(ph), 0.3 * std::sin(th) * std::sin(ph), 0.3 * std::cos(th)});
        }
    return p;
}

template <class T>
void put(std::string& s, T v, bool big = false) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    if (big) std::reverse(b, b + sizeof v);
    s.append(b, sizeof v);
}

std::string text_points(const char* sep, bool comma_decimal, const std::string& head) {
    std::string s = head;
    char line[128];
    for (const auto& p : sphere(10)) {
        std::snprintf(line, sizeof line, "%.6f%s%.6f%s%.6f%s7\n", p[0], sep, p[1], sep, p[2], sep);
        std::string l = line;
        if (comma_decimal)
            for (char& c : l)
                if (c == '.') c = ',';
        s += l;
    }
    return s;
}

std::string ply(const char* format) {
    const auto pts = sphere(10);
    const bool ascii = std::string(format) == "ascii", big = std::string(format) == "binary_big_endian";
    std::string s = std::string("ply\nformat ") + format + " 1.0\ncomment corruption base\nelement camera 1\nproperty float f\n" +
                    "element vertex " + std::to_string(pts.size()) +
                    "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\n"
                    "property list uchar int extra\nend_header\n";
    if (ascii) {
        s += "1.5\n";
        char line[160];
        for (const auto& p : pts) {
            std::snprintf(line, sizeof line, "%.9g %.9g %.9g 200 2 4 5\n", p[0], p[1], p[2]);
            s += line;
        }
    } else {
        put(s, 1.5f, big);
        for (const auto& p : pts) {
            for (double x : p) put(s, x, big);
            put(s, std::uint8_t(200));
            put(s, std::uint8_t(2));
            put(s, std::int32_t(4), big);
            put(s, std::int32_t(5), big);
        }
    }
    return s;
}

std::string las() {
    std::vector<std::array<double, 3>> pts = sphere(10);
    for (auto& p : pts)
        for (double& x : p) x += 1000;
    return snvr::testing::las_file(pts, 0.0001, 1000, '\x11');
}

// An octahedron, as binary STL and as OBJ with faces (a mesh to thicken).
const double kOcta[6][3] = {{0.3, 0, 0}, {-0.3, 0, 0}, {0, 0.3, 0}, {0, -0.3, 0}, {0, 0, 0.3}, {0, 0, -0.3}};
const int kOctaFaces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

std::string stl() {
    std::string s(80, ' ');
    put(s, std::uint32_t(8));
    for (const auto& f : kOctaFaces) {
        for (int k = 0; k < 3; ++k) put(s, 0.0f);
        for (int c : f)
            for (double x : kOcta[c]) put(s, float(x));
        put(s, std::uint16_t(0));
    }
    return s;
}

std::string obj_mesh() {
    std::string s = "# octahedron\n";
    for (const auto& v : kOcta) s += "v " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
    for (const auto& f : kOctaFaces)
        s += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
    return s;
}

struct Format {
    std::string name;  // file name, whose extension picks the reader
    std::string bytes;
    bool gzipped = false;  // mutate the plain text, then compress (half the time)
};

std::vector<Format> formats() {
    std::string off = "OFF\n" + std::to_string(sphere(10).size()) + " 0 0\n";
    for (const auto& p : sphere(10)) off += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    std::string obj_points = "# points\n";
    for (const auto& p : sphere(10))
        obj_points += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    return {{"ascii.ply", ply("ascii")},
            {"little.ply", ply("binary_little_endian")},
            {"big.ply", ply("binary_big_endian")},
            {"points.xyz", text_points(" ", false, "")},
            {"points.csv", text_points(",", false, "X,Y,Z,I\n")},
            {"points.txt", text_points(";", true, "//X;Y;Z;I\r\n")},
            {"points.obj", obj_points},
            {"points.off", off},
            {"points.las", las()},
            {"points.xyz.gz", text_points(" ", false, ""), true},
            {"mesh.stl", stl()},
            {"mesh.obj", obj_mesh()}};
}

// A field of the header made absurd: the counts, offsets and sizes a reader trusts (LAS
// and binary STL by their byte offsets; text headers by their numbers; gzip's trailer,
// which states the inflated size and CRC). Structure-aware, where mutate() is blind.
std::string mutate_header(std::string s, const std::string& name, std::mt19937_64& g) {
    const auto pick = [&](std::size_t n) { return n ? std::size_t(g() % n) : 0; };
    const std::uint64_t absurd[] = {0, 1, 0x7FFFFFFF, 0xFFFFFFFF, s.size(), s.size() + 1, s.size() / 2};
    const auto poke = [&](std::size_t at, std::size_t bytes) {
        if (at + bytes > s.size()) return;
        const std::uint64_t v = absurd[pick(std::size(absurd))];
        for (std::size_t b = 0; b < bytes; ++b) s[at + b] = char((v >> (8 * b)) & 0xFF);
    };
    const std::string ext = name.substr(name.find('.'));
    if (ext == ".xyz.gz") {  // a trailer that lies about the size or the CRC
        poke(s.size() - 4 * (1 + pick(2)), 4);
    } else if (ext == ".las") {
        const std::size_t fields[][2] = {{94, 2}, {96, 4}, {100, 4}, {104, 1}, {105, 2}, {107, 4}, {131, 8}, {155, 8}};
        const auto& f = fields[pick(std::size(fields))];
        if (f[1] == 8) {  // a scale or an offset: a double that makes no coordinates
            const double d[] = {0.0, 1e-320, 1e308, -1e308, std::nan(""), HUGE_VAL};
            const double v = d[pick(std::size(d))];
            if (f[0] + 8 <= s.size()) std::memcpy(&s[f[0]], &v, 8);
        } else {
            poke(f[0], f[1]);
        }
    } else if (name == "mesh.stl") {
        poke(80, 4);  // the triangle count
    } else {  // a number of the text header (PLY up to end_header, else the first lines)
        const std::size_t end = std::min(s.size(), ext == ".ply" ? s.find("end_header") : std::size_t(64));
        std::vector<std::size_t> starts;
        for (std::size_t i = 0; i < end; ++i)
            if (std::isdigit(static_cast<unsigned char>(s[i])) && (i == 0 || !std::isdigit(static_cast<unsigned char>(s[i - 1]))))
                starts.push_back(i);
        if (starts.empty()) return s;
        const std::size_t at = starts[pick(starts.size())];
        std::size_t stop = at;
        while (stop < s.size() && std::isdigit(static_cast<unsigned char>(s[stop]))) ++stop;
        static const char* const kCounts[] = {"0", "-1", "4294967295", "18446744073709551615", "99999999999", "2"};
        s.replace(at, stop - at, kCounts[pick(std::size(kCounts))]);
    }
    return s;
}

// One mutation of `s`, chosen and placed by the generator.
std::string mutate(std::string s, std::mt19937_64& g) {
    const auto pick = [&](std::size_t n) { return n ? std::size_t(g() % n) : 0; };
    static const char* const kNumbers[] = {"99999999999999999999", "-1", "nan", "1e309", "0", "-0", "1e-400",
                                           "18446744073709551615", "4294967296", "inf", "0x10", ""};
    switch (g() % 8) {
        case 0:  // bytes flipped
            for (std::size_t k = 1 + pick(8); k-- && !s.empty();) s[pick(s.size())] = char(g());
            break;
        case 1:  // cut short
            s.resize(pick(s.size() + 1));
            break;
        case 2: {  // bytes inserted
            std::string junk(1 + pick(16), '\0');
            for (char& c : junk) c = char(g());
            s.insert(pick(s.size() + 1), junk);
            break;
        }
        case 3: {  // a range deleted
            const std::size_t at = pick(s.size() + 1);
            s.erase(at, 1 + pick(64));
            break;
        }
        case 4: {  // a range duplicated
            const std::size_t at = pick(s.size() + 1), n = 1 + pick(256);
            s.insert(at, s.substr(at, n));
            break;
        }
        case 5: {  // a run of digits made absurd (counts, coordinates, indices)
            std::size_t at = pick(s.size() + 1);
            while (at < s.size() && !std::isdigit(static_cast<unsigned char>(s[at]))) ++at;
            std::size_t end = at;
            while (end < s.size() && std::isdigit(static_cast<unsigned char>(s[end]))) ++end;
            s.replace(at, end - at, kNumbers[pick(std::size(kNumbers))]);
            break;
        }
        case 6:  // a NUL, a CR or a byte-order mark in the middle
            s.insert(pick(s.size() + 1), std::string(g() % 3 == 0 ? "\xEF\xBB\xBF" : g() % 2 ? "\r" : std::string(1, '\0')));
            break;
        default:  // a stretch overwritten with one byte
            if (!s.empty()) {
                const std::size_t at = pick(s.size()), n = std::min(s.size() - at, 1 + pick(32));
                std::fill_n(s.begin() + std::ptrdiff_t(at), n, char(g()));
            }
    }
    return s;
}

struct Outcome {
    std::string file;
    int code = -2;        // exit status; -1 for a signal, -3 for a timeout
    std::string message;  // stderr
    std::vector<std::string> left;  // the directory's entries afterwards
};

Outcome run_one(const fs::path& dir, const std::string& name, const std::string& bytes) {
    Outcome o;
    o.file = (dir / name).string();
    std::ofstream(o.file, std::ios::binary) << bytes;
    const std::string out = (dir / "shell.stl").string();
    const snvr::testing::BoundedRun r = snvr::testing::run_bounded(
        {SNVR_CLI, "reconstruct", o.file, "-o", out, "--resolution", "24", "--device", "openmp", "--quiet"}, "",
        (dir / "stderr.txt").string(), kTimeLimit);
    o.code = r.code;
    o.message = r.stderr_text;
    for (const auto& e : fs::directory_iterator(dir)) o.left.push_back(e.path().filename().string());
    return o;
}

}  // namespace

TEST_CASE("corruption campaign: no crash, no hang, exit 1 naming the file, nothing left behind") {
    snvr::testing::TempDir root("corruption");
    struct Job {
        std::string name, bytes;
    };
    std::vector<Job> jobs;
    std::uint64_t seed = 20261123;
    for (const Format& f : formats()) {
        std::mt19937_64 g(seed++);
        for (int i = 0; i < kMutationsPerFormat; ++i) {
            std::string bytes;
            if (i % 4 == 3) {  // every fourth: a header field, knowing the format
                bytes = f.gzipped ? mutate_header(snvr::testing::gzip(f.bytes), f.name, g) : mutate_header(f.bytes, f.name, g);
            } else {
                bytes = mutate(f.bytes, g);
                if (f.gzipped) bytes = i % 2 ? snvr::testing::gzip(bytes) : mutate(snvr::testing::gzip(f.bytes), g);
            }
            jobs.push_back({f.name, std::move(bytes)});
        }
    }
    // Two at a time, each in a directory of its own.
    std::vector<Outcome> outcomes(jobs.size());
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> workers;
    for (int w = 0; w < 2; ++w)
        workers.emplace_back([&, w] {
            const fs::path dir = root.path / ("w" + std::to_string(w));
            for (std::size_t i; (i = next++) < jobs.size();) {
                fs::create_directories(dir);
                outcomes[i] = run_one(dir, jobs[i].name, jobs[i].bytes);
                fs::remove_all(dir);
            }
        });
    for (auto& t : workers) t.join();

    std::map<std::string, std::array<int, 2>> tally;  // format: {ok, refused}
    std::map<std::string, int> placeless;             // refusals that name no place in the file
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const Outcome& o = outcomes[i];
        CAPTURE(jobs[i].name);
        CAPTURE(i);
        CAPTURE(o.message);
        REQUIRE(o.code >= 0);  // no crash (signal), no hang (timeout), spawned
        CHECK((o.code == 0 || o.code == 1));
        if (o.code == 0) {
            CHECK(o.left.size() == 2);  // the input and the shell
            ++tally[jobs[i].name][0];
        } else {
            CHECK(o.left == std::vector<std::string>{jobs[i].name});  // no output, no temporary
            CHECK(o.message.rfind("snvr-cl: error: ", 0) == 0);
            // Names the input, or the output when that is what cannot be written.
            CHECK((o.message.find(o.file) != std::string::npos || o.message.find("cannot write") != std::string::npos));
            ++tally[jobs[i].name][1];
            bool place = false;
            for (const char* word : {"line ", "byte", "offset", "point", "vertex", "vertices", "header", "face",
                                     "triangle", "element", "record", "items", "signature", "gzip"})
                place = place || o.message.find(word) != std::string::npos;
            if (!place) {
                std::string line = o.message.substr(0, o.message.find('\n'));
                const std::size_t at = line.find(o.file);
                if (at != std::string::npos) line.replace(at, o.file.size(), jobs[i].name);
                ++placeless[line];
            }
        }
    }
    for (const auto& [name, counts] : tally)
        MESSAGE(name << ": " << counts[0] << " read and reconstructed, " << counts[1] << " refused");
    for (const auto& [message, count] : placeless) MESSAGE(count << " refused naming no place: " << message);
}
