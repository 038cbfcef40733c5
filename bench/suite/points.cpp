#include "points.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "program_runs.hpp"

namespace snvr::bench {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The sampler's shapes, with their area: points are about area / spacing^2 (from its
// counts at spacing 0.004: sphere 96,212, torus 89,162, helicoid 75,766).
struct Shape {
    const char* name;
    double area;
};
constexpr Shape kShapes[] = {{"noisy-sphere", 1.539}, {"torus", 1.427}, {"helicoid", 1.212}};
// Each halving of the spacing is four times the points: 96 k to 24.6 M on the sphere.
constexpr double kSpacings[] = {0.004, 0.002, 0.001, 0.0005, 0.00025};
// Scans with fewer points than this are left out unless named: below it the run is
// all fixed costs, whatever the points.
constexpr double kLeastScanPoints = 30000;

struct Cloud {
    std::string family;
    double spacing = 0;  // a shape's: the sampler's --spacing
    std::string scan;    // a scan's file
    double points = 0;   // a scan's count, a shape's estimate (for --points-max)
    std::string label() const {
        if (!scan.empty()) return family;
        char s[64];
        std::snprintf(s, sizeof s, "%s %g", family.c_str(), spacing);
        return s;
    }
};

// A PLY file's vertex count, from its header (the scans are small; no need to read them here).
double ply_vertices(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    while (std::getline(in, line) && line.rfind("end_header", 0) != 0)
        if (line.rfind("element vertex ", 0) == 0) return std::atof(line.c_str() + 15);
    return 0;
}

std::vector<Cloud> scans(const std::string& data) {
    std::vector<Cloud> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(data, ec))
        if (e.path().extension() == ".ply") {
            Cloud c;
            c.family = e.path().stem().string();
            c.scan = e.path().string();
            c.points = ply_vertices(c.scan);
            out.push_back(c);
        }
    std::sort(out.begin(), out.end(), [](const Cloud& a, const Cloud& b) { return a.points < b.points; });
    return out;
}

std::vector<Cloud> plan_clouds(const PointsOptions& o) {
    std::vector<Cloud> all;
    if (o.quick) {
        for (double s : {0.009, 0.0064}) all.push_back({"noisy-sphere", s, "", kShapes[0].area / (s * s)});
        return all;
    }
    const auto named = [&](const std::string& f) { return o.clouds.empty() || std::count(o.clouds.begin(), o.clouds.end(), f); };
    for (const Shape& shape : kShapes)
        if (named(shape.name))
            for (double s : kSpacings) all.push_back({shape.name, s, "", shape.area / (s * s)});
    for (const Cloud& c : scans(o.data))
        if (o.clouds.empty() ? c.points >= kLeastScanPoints : named(c.family)) all.push_back(c);
    for (const std::string& f : o.clouds)
        if (std::none_of(all.begin(), all.end(), [&](const Cloud& c) { return c.family == f; }))
            std::fprintf(stderr, "snvr-bench: points: no cloud '%s' (a shape of the sampler or a scan in %s); skipped\n", f.c_str(),
                         o.data.c_str());
    std::vector<Cloud> kept;
    for (const Cloud& c : all)
        if (c.points <= o.max_points) kept.push_back(c);
        else std::fprintf(stderr, "snvr-bench: points: %s (about %.3g points) is above --points-max; skipped\n", c.label().c_str(), c.points);
    return kept;
}

// The distance + marching cubes peer: its stages from the JSON line it prints last.
void measure_distance_peer(const PointsPrograms& p, const std::string& cloud, const Lengths& l, const std::string& dir, Record& r) {
    const std::optional<ProgramRun> run = run_peer("distance_mc", p.distance_mc_peer, cloud, l, dir, r);
    if (!run) return;
    try {
        const json line = json::parse(run->output.substr(run->output.rfind('{', run->output.rfind("\"points\""))));
        for (const char* stage : {"read", "index", "band", "distance", "mesh", "write", "total"})
            r.set(std::string("distance_mc_") + stage + "_s", line.at("seconds").at(stage).get<double>());
        r.set("distance_mc_band_cells", line.at("band_cells").get<double>()).set("distance_mc_triangles", line.at("triangles").get<double>());
    } catch (const std::exception& e) {
        r.set("distance_mc_error", std::string("reading its JSON line: ") + e.what());
    }
}

// Short runs are the noisiest on a shared machine, and the smallest clouds are the base
// of the cost per point: a program whose first run took under this runs `repeat` times
// and its median run is kept, with the spread.
constexpr double kRepeatBelowSeconds = 10;

void measure_repeated(const std::string& program, int repeat, Record& row, const std::function<void(Record&)>& once) {
    const std::string seconds = program + "_process_s";
    std::vector<Record> runs;
    do {
        Record r;
        once(r);
        runs.push_back(r);
        if (r.has(program + "_error") || !r.has(seconds)) {  // failed, or not built: no median
            row = Record::deserialize(row.serialize() + r.serialize());
            return;
        }
    } while (int(runs.size()) < repeat && runs.front().number(seconds) < kRepeatBelowSeconds);
    std::sort(runs.begin(), runs.end(), [&](const Record& a, const Record& b) { return a.number(seconds) < b.number(seconds); });
    row = Record::deserialize(row.serialize() + runs[runs.size() / 2].serialize());
    row.set(program + "_runs", double(runs.size())).set(program + "_process_min_s", runs.front().number(seconds));
    row.set(program + "_process_max_s", runs.back().number(seconds));
}

// Ours over each peer, in seconds and in peak memory.
void set_ratios(Record& r) {
    for (const char* peer : {"distance_mc", "openvdb"}) {
        const std::string p = peer;
        if (!r.has("snvr_process_s") || !r.has(p + "_process_s") || r.has("snvr_error") || r.has(p + "_error")) continue;
        r.set("snvr_over_" + p + "_s", r.number("snvr_process_s") / r.number(p + "_process_s"));
        r.set("snvr_over_" + p + "_mib", r.number("snvr_peak_mib") / r.number(p + "_peak_mib"));
    }
}

const char* const kPrograms[] = {"snvr", "distance_mc", "openvdb"};

bool measured(const Record& r, const std::string& program) { return r.has(program + "_process_s") && !r.has(program + "_error"); }

// What each extra point costs against the family's smallest cloud at the same grid:
// (t(N) - t(N0)) / (N - N0) in nanoseconds, of whole-process wall-clock seconds and of
// CPU seconds.
void set_cost_per_point(Record& r, const Record& base) {
    const double extra = r.number("points") - base.number("points");
    if (!(extra > 0)) return;
    r.set("base_points", base.number("points"));
    for (const char* program : kPrograms) {
        const std::string p = program;
        if (!measured(r, p) || !measured(base, p)) continue;
        r.set(p + "_ns_per_point", 1e9 * (r.number(p + "_process_s") - base.number(p + "_process_s")) / extra);
        r.set(p + "_cpu_ns_per_point", 1e9 * (r.number(p + "_cpu_s") - base.number(p + "_cpu_s")) / extra);
    }
}

}  // namespace

void run_points(const PointsOptions& o, const PointsPrograms& p, const std::function<void(const Record&)>& keep) {
    const std::vector<int> grids = o.quick ? std::vector<int>{64} : o.grids;
    const std::vector<Cloud> clouds = plan_clouds(o);
    const std::string dir = o.scratch + "/run";
    fs::create_directories(dir);
    const auto base = [&](const Cloud& c, int grid) {
        Record r;
        r.set("section", "points").set("case", c.label()).set("family", c.family).set("resolution", grid);
        r.set("device", o.device.empty() ? "auto" : o.device);
        if (c.spacing > 0) r.set("spacing", c.spacing);
        return r;
    };
    std::map<std::string, Record> smallest;  // family and grid: its first row, the cost per point's base
    bool warm = false;
    std::size_t done = 0;
    for (const Cloud& c : clouds) {
        std::string path = c.scan;
        if (path.empty()) {
            char name[64];
            std::snprintf(name, sizeof name, "/%s-%g.ply", c.family.c_str(), c.spacing);
            path = o.scratch + name;
            const ProgramRun made = run_program({p.snvr_cl, "sample", c.family, "-o", path, "--spacing", exact(c.spacing)});
            if (!made.ok()) {
                for (int grid : grids) keep(base(c, grid).set("error", "sampling it: " + made.why()));
                continue;
            }
        }
        if (!warm) {  // the first run on a device builds its kernels (then cached): not in a measured run
            run_program({p.snvr_cl, "reconstruct", path, "-o", dir + "/warm-up.stl", "--resolution", "32", "--quiet"});
            warm = true;
        }
        for (int grid : grids) {
            std::fprintf(stderr, "[points %zu/%zu] %s (about %.3g points) at %d cells\n", ++done, clouds.size() * grids.size(),
                         c.label().c_str(), c.points, grid);
            Record r = base(c, grid);
            Lengths lengths;
            measure_repeated("snvr", o.repeat, r, [&](Record& run) { measure_ours(p.snvr_cl, o.device, path, grid, dir, run, lengths); });
            if (!r.has("snvr_error")) {
                measure_repeated("distance_mc", o.repeat, r, [&](Record& run) { measure_distance_peer(p, path, lengths, dir, run); });
                measure_repeated("openvdb", o.repeat, r, [&](Record& run) { measure_openvdb_peer(p.openvdb_peer, path, lengths, dir, run); });
                set_ratios(r);
            }
            const std::string key = c.family + "/" + std::to_string(grid);
            if (!smallest.count(key) && measured(r, "snvr")) smallest[key] = r;
            else if (smallest.count(key) && c.scan.empty()) set_cost_per_point(r, smallest[key]);
            for (const char* out : {"snvr.stl", "snvr.json", "distance_mc.stl", "openvdb.stl"}) fs::remove(dir + "/" + out);
            keep(r);
        }
        if (c.scan.empty()) fs::remove(path);
    }
    fs::remove_all(dir);
}

}  // namespace snvr::bench
