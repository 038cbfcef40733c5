// snvr-bench: the benchmark suite. Runs the paper's Table 1 and Table 2 cases, a
// roofline per device and a scaling series on every available device and precision
// (or a chosen subset), each case in its own process with a warm-up and repetitions,
// then the quality comparison with the OpenVDB peer (quality.hpp: once, on the default
// device or the first of --devices) and the cost against the number of points
// (points.hpp: snvr-cl and the peers as processes, once), tiled runs against whole
// ones (tiles.hpp, once) and each stage against its unit of work and its floor
// (stages.hpp, beside the OpenVDB peer), and writes results.jsonl,
// results.md (and points.md), the data for bench/plots.gp and the quality section's
// PNG previews.
//
//   snvr-bench [--quick] [--sections table1,table2,roofline,scaling,quality,points,tiles,stages] [--devices D1,D2]
//              [--precisions double,float] [--repeat N] [--table2 128,256,512] [--scaling 128,256,384,512]
//              [--data DIR] [--out DIR]
//              [--quality-resolutions 128,256,512] [--quality-cases bunny,sheets,...] [--quality-reference 256]
//              [--points-clouds noisy-sphere,torus,bunny,...] [--points-max N] [--points-grids 256,512] [--points-scratch DIR]
//              [--tiles-cases bunny@512/128,lidar@256/64,...] [--stages-cases bunny@256,bunny@1024,...]
// Cases above 256 cells on the longest axis run once, without a warm-up (minutes each).
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "isolated.hpp"
#include "measure.hpp"
#include "points.hpp"
#include "points_report.hpp"
#include "quality.hpp"
#include "report.hpp"
#include "stages.hpp"
#include "tiles.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;
using namespace snvr::bench;

namespace {

struct Options {
    bool quick = false;
    std::set<std::string> sections{"table1", "table2", "roofline", "scaling", "quality", "points", "tiles", "stages"};
    std::vector<std::string> devices, precisions;  // empty: all available / by mode
    int repeat = 3;
    std::vector<int> table2{128, 256, 512};  // 512^3 where memory allows (else "not measured")
    std::vector<int> scaling{128, 256, 384, 512};
    int roofline = 256;  // the roofline's grid (a GPU needs more cells than launches to be measured)
    std::string data = SNVR_DATA_DIR, out = "snvr-bench-results";
    std::vector<int> quality_resolutions{128, 256, 512};
    std::vector<std::string> quality_cases;  // empty: all (--quick: bunny and sheets)
    int quality_reference = 256;             // the grid a case's offset is given in (--quick: 64)
    PointsOptions points;                    // its device and data are filled in from the above
    TilesOptions tiles;                      // likewise
    StagesOptions stages;                    // likewise
};

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> v;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, ','))
        if (!item.empty()) v.push_back(item);
    return v;
}

std::vector<int> resolutions(const std::string& s) {
    std::vector<int> v;
    for (const std::string& n : split(s)) v.push_back(std::atoi(n.c_str()));
    return v;
}

int usage(const char* why) {
    std::fprintf(stderr,
                 "snvr-bench: %s\nusage: snvr-bench [--quick] [--sections table1,table2,roofline,scaling,quality,points,tiles,stages] [--devices D1,D2]\n"
                 "                  [--precisions double,float] [--repeat N] [--table2 128,256,512] [--scaling 128,256,384,512]\n"
                 "                  [--roofline-resolution 256] [--data DIR] [--out DIR]\n"
                 "                  [--quality-resolutions 128,256,512] [--quality-cases bunny,sheets,...] [--quality-reference 256]\n"
                 "                  [--points-clouds noisy-sphere,torus,helicoid,bunny,...] [--points-max N (7000000)]\n"
                 "                  [--points-grids 256,512] [--points-scratch DIR ($TMPDIR/snvr-bench-points-PID)]\n"
                 "                  [--tiles-cases CLOUD@CELLS/TILE,... (bunny@256/128,bunny@512/128,lidar@256/64)]\n"
                 "                  [--stages-cases SCAN@CELLS,... (bunny@256,bunny@1024)]\n",
                 why);
    return 2;
}

// Every other point of a scan: the paper's point counts are those (data/SOURCES.md).
PointSet every_other(const PointSet& p) {
    PointSet out;
    for (std::size_t i = 0; i < p.size(); i += 2) out.push_back(p[i]);
    return out;
}

struct Plan {
    std::vector<RunCase> runs;
    std::vector<std::pair<std::string, std::function<PointSet()>>> roofline;  // label, points
    int roofline_resolution = 256;
};

Plan plan_cases(const Options& o) {
    Plan plan;
    const std::string data = o.data;
    const auto scan = [data](const std::string& file) { return [data, file] { return read_points(data + "/" + file); }; };
    const auto half_bunny = [data] { return every_other(read_points(data + "/bunny.ply")); };
    const auto run = [](const std::string& section, const std::string& name, std::function<PointSet()> pts, int resolution, int steps) {
        RunCase c;
        c.section = section;
        c.name = name;
        c.points = std::move(pts);
        c.params.resolution = resolution;
        c.params.steps = steps;
        return c;
    };
    const int q = o.quick ? 1 : 0;  // quick: smaller grids, 2 steps
    if (o.sections.count("table1")) {
        // The paper's cases we can make or have; its seconds only where we know them
        // (DESIGN.md: bunny 167.32 s; the happy Buddha is not in ../shared/data).
        RunCase hs = run("table1", "half sphere (Fig. 5)", [] { return shapes::by_name("half-sphere", 0.004); }, q ? 64 : 128, q ? 2 : 4);
        RunCase cone = run("table1", "two-headed cone (Fig. 6)", [] { return shapes::by_name("cone", 0.004); }, q ? 64 : 128, q ? 2 : 8);
        RunCase bunny = run("table1", "bunny, every other point", half_bunny, q ? 64 : 256, q ? 2 : 6);
        bunny.params.precision = Precision::Double;
        plan.runs.insert(plan.runs.end(), {hs, cone, bunny});
        if (!q)
            for (const char* f : {"armadillo.ply", "cactus.ply", "distcap.ply", "dragon.ply", "horse.ply", "igea.ply"})
                plan.runs.push_back(run("table1", f, scan(f), 256, 6));
    }
    if (o.sections.count("table2"))
        for (const char* shape : {"sphere", "cube", "cylinder"})
            for (int n : q ? std::vector<int>{32, 64} : o.table2) {
                RunCase c = run("table2", shape, [shape, n] { return shapes::by_name(shape, 0.5 / n); }, n, q ? 2 : 4);
                c.params.box = std::array<Vec3, 2>{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
                c.params.offset = 0.05;
                c.params.eps = 0.005;
                c.table2_shape = shape;
                plan.runs.push_back(c);
            }
    if (o.sections.count("scaling"))
        for (int n : q ? std::vector<int>{48, 64, 96} : o.scaling)
            plan.runs.push_back(run("scaling", "bunny", scan("bunny.ply"), n, q ? 2 : 6));
    if (o.sections.count("roofline")) {
        plan.roofline.push_back({"bunny", scan("bunny.ply")});
        plan.roofline_resolution = q ? 96 : o.roofline;
    }
    return plan;
}

// The quality section: every case at every resolution, ours and the OpenVDB peer,
// each in its own process; previews at the middle resolution.
void run_quality(const Options& o, const std::string& device, std::ofstream& jsonl, std::vector<Record>& records) {
    const std::vector<std::string> known_shapes = shapes::names();
    std::vector<std::string> wanted = o.quality_cases;
    if (wanted.empty() && o.quick) wanted = {"bunny", "sheets"};
    std::vector<QualityCase> cases;
    for (const QualityCase& c : quality_cases(o.data, !o.quick)) {
        if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), c.name) == wanted.end()) continue;
        if (!c.shape.empty() && std::find(known_shapes.begin(), known_shapes.end(), c.shape) == known_shapes.end()) {
            std::fprintf(stderr, "snvr-bench: quality: shape '%s' is not in shapes::by_name yet; skipped\n", c.shape.c_str());
            continue;
        }
        cases.push_back(c);
    }
    for (const std::string& w : wanted) {
        bool found = false;
        for (const QualityCase& c : cases) found |= c.name == w;
        if (!found) std::fprintf(stderr, "snvr-bench: quality: no case '%s' (a scan in %s or a shape); skipped\n", w.c_str(), o.data.c_str());
    }
    std::vector<int> resolutions = o.quick ? std::vector<int>{64, 80} : o.quality_resolutions;
    std::sort(resolutions.begin(), resolutions.end());
    const int middle = resolutions[resolutions.size() / 2];
    const std::size_t total = cases.size() * resolutions.size() * 2;
    std::size_t done = 0;
    for (const QualityCase& c : cases)
        for (int n : resolutions)
            for (const char* tool : {"snvr", "openvdb"}) {
                ++done;
                const auto base = [&] { return Record().set("section", "quality").set("case", c.name).set("resolution", n).set("tool", tool); };
                std::vector<Record> rs;
                if (std::string(tool) == "openvdb" && !quality_has_openvdb()) {
                    rs = {base().set("note", "not built (needs libopenvdb-dev and libboost-dev at configure time)")};
                } else {
                    QualityRun run;
                    run.c = c;
                    run.resolution = n;
                    run.reference = o.quick ? 64 : o.quality_reference;
                    run.tool = tool;
                    run.device = device;
                    if (n == middle) run.png_dir = o.out;
                    run.png_size = o.quick ? 512 : 1024;
                    std::fprintf(stderr, "[quality %zu/%zu] %s at %d cells, %s\n", done, total, c.name.c_str(), n, tool);
                    rs = run_isolated([&] { return std::vector<Record>{measure_quality_run(run, o.data)}; });
                    for (Record& r : rs)
                        if (r.has("error")) {
                            const std::string why = r.text("error");
                            r = base().set("error", why);
                        }
                }
                for (const Record& r : rs) {
                    jsonl << r.json() << '\n';
                    jsonl.flush();
                    records.push_back(r);
                }
            }
}

// A scratch folder of the section's own under $TMPDIR (else /tmp).
std::string scratch_folder(const std::string& section) {
    const char* tmp = std::getenv("TMPDIR");
    return std::string(tmp && *tmp ? tmp : "/tmp") + "/snvr-bench-" + section + "-" + std::to_string(::getpid());
}

// Each record as it comes: written out at once and kept.
std::function<void(const Record&)> keeper(std::ofstream& jsonl, std::vector<Record>& records) {
    return [&jsonl, &records](const Record& r) {
        jsonl << r.json() << '\n';
        jsonl.flush();
        records.push_back(r);
    };
}

// What the sections that run programs take from the suite's options.
template <class SectionOptions>
void share_options(const Options& o, SectionOptions& section) {
    section.quick = o.quick;
    section.data = o.data;
    section.repeat = o.repeat;
    if (!o.devices.empty()) section.device = o.devices.front();
}

// The points section: snvr-cl and the peers, each run a process of its own.
void run_points_section(Options& o, std::ofstream& jsonl, std::vector<Record>& records) {
    PointsOptions& po = o.points;
    share_options(o, po);
    if (po.scratch.empty()) po.scratch = scratch_folder("points");
    const PointsPrograms programs{SNVR_CL_PROGRAM, SNVR_DISTANCE_MC_PEER_PROGRAM, SNVR_OPENVDB_PEER_PROGRAM};
    const auto keep = keeper(jsonl, records);
    try {
        run_points(po, programs, keep);
    } catch (const std::exception& e) {
        keep(Record().set("section", "points").set("case", "the section").set("error", e.what()));
    }
    std::error_code ignored;
    std::filesystem::remove(po.scratch, ignored);  // only when nothing of the user's is left in it
}

// The tiles section: snvr-cl whole and tiled, in turn.
void run_tiles_section(Options& o, std::ofstream& jsonl, std::vector<Record>& records) {
    TilesOptions& to = o.tiles;
    share_options(o, to);
    to.scratch = scratch_folder("tiles");
    run_tiles(to, SNVR_CL_PROGRAM, keeper(jsonl, records));
}

// The stages section: snvr-cl's stages by their units and floors, beside the OpenVDB peer.
void run_stages_section(Options& o, std::ofstream& jsonl, std::vector<Record>& records) {
    StagesOptions& so = o.stages;
    share_options(o, so);
    so.scratch = scratch_folder("stages");
    run_stages(so, SNVR_CL_PROGRAM, SNVR_OPENVDB_PEER_PROGRAM, keeper(jsonl, records));
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int a = 1; a < argc; ++a) {
        const std::string opt = argv[a];
        if (opt == "--quick") {
            o.quick = true;
            continue;
        }
        if (a + 1 >= argc) return usage(("missing value for " + opt).c_str());
        const std::string val = argv[++a];
        if (opt == "--sections") {
            const std::vector<std::string> v = split(val);
            o.sections = std::set<std::string>(v.begin(), v.end());
        }
        else if (opt == "--devices") o.devices = split(val);
        else if (opt == "--precisions") o.precisions = split(val);
        else if (opt == "--repeat") o.repeat = std::atoi(val.c_str());
        else if (opt == "--scaling") o.scaling = resolutions(val);
        else if (opt == "--roofline-resolution") o.roofline = std::atoi(val.c_str());
        else if (opt == "--data") o.data = val;
        else if (opt == "--table2") o.table2 = resolutions(val);
        else if (opt == "--out") o.out = val;
        else if (opt == "--quality-resolutions") o.quality_resolutions = resolutions(val);
        else if (opt == "--quality-cases") o.quality_cases = split(val);
        else if (opt == "--quality-reference") o.quality_reference = std::atoi(val.c_str());
        else if (opt == "--points-clouds") o.points.clouds = split(val);
        else if (opt == "--points-max") o.points.max_points = std::atof(val.c_str());
        else if (opt == "--points-grids") o.points.grids = resolutions(val);
        else if (opt == "--points-scratch") o.points.scratch = val;
        else if (opt == "--tiles-cases") o.tiles.cases = split(val);
        else if (opt == "--stages-cases") o.stages.cases = split(val);
        else return usage(("unknown option " + opt).c_str());
    }
    if (o.repeat < 1) return usage("--repeat must be at least 1");
    for (int n : o.quality_resolutions)
        if (n < 8) return usage("--quality-resolutions must be at least 8 cells");
    if (o.quality_resolutions.empty()) return usage("--quality-resolutions is empty");
    for (int n : o.scaling)
        if (n < 8) return usage("--scaling must be at least 8 cells");
    if (o.quality_reference < 8) return usage("--quality-reference must be at least 8 cells");
    if (o.points.grids.empty()) return usage("--points-grids is empty");
    for (int n : o.points.grids)
        if (n < 32) return usage("--points-grids must be at least 32 cells");
    if (!(o.points.max_points > 0)) return usage("--points-max must be a positive number of points");
    if (o.quick) o.repeat = 1;
    if (o.precisions.empty()) o.precisions = o.quick ? std::vector<std::string>{"double"} : std::vector<std::string>{"double", "float"};

    // Devices, found in a child like everything that touches OpenCL.
    std::vector<Record> found = run_isolated(list_device_records);
    std::vector<std::pair<std::string, bool>> devices;  // id, fp64
    for (const Record& r : found) {
        if (r.has("error")) {
            std::fprintf(stderr, "snvr-bench: listing devices: %s\n", r.text("error").c_str());
            return 1;
        }
        bool wanted = o.devices.empty();
        for (const std::string& d : o.devices) wanted |= d == r.text("device");
        if (wanted) devices.push_back({r.text("device"), r.text("fp64") == "yes"});
    }
    if (devices.empty()) return usage("none of the --devices is available; see snvr-cl devices");
    for (const std::string& d : o.devices) {  // each one asked for is measured, or named here
        bool listed = false;
        for (const auto& entry : devices) listed |= entry.first == d;
        if (!listed) return usage(("no device '" + d + "' (IDs as snvr-cl devices lists them, e.g. opencl:0:0)").c_str());
    }

    mkdir(o.out.c_str(), 0755);
    const Plan plan = plan_cases(o);
    std::vector<Record> records;
    std::ofstream jsonl(o.out + "/results.jsonl");
    if (!jsonl) {
        std::fprintf(stderr, "snvr-bench: cannot write %s/results.jsonl\n", o.out.c_str());
        return 1;
    }
    const auto keep = [&](std::vector<Record> rs, const std::string& section, const std::string& name, const std::string& device,
                          const std::string& precision) {
        for (Record& r : rs) {
            if (r.has("error")) r.set("section", section).set("case", name).set("device", device).set("precision", precision);
            jsonl << r.json() << '\n';
            jsonl.flush();
            records.push_back(r);
        }
    };
    const std::size_t total = (plan.runs.size() + plan.roofline.size()) * devices.size() * o.precisions.size();
    std::size_t done = 0;
    for (const auto& [device, fp64] : devices)
        for (const std::string& precision : o.precisions) {
            if (precision == "double" && !fp64) continue;
            for (RunCase c : plan.runs) {
                c.params.device = device;
                c.params.precision = precision == "float" ? Precision::Single : Precision::Double;
                std::fprintf(stderr, "[%zu/%zu] %s %s on %s, %s\n", ++done, total, c.section.c_str(), c.name.c_str(), device.c_str(),
                             precision.c_str());
                const bool big = c.params.resolution > 256;
                keep(run_isolated([&] { return std::vector<Record>{measure_run(c, big ? 1 : o.repeat, !big)}; }), c.section, c.name, device,
                     precision);
            }
            for (const auto& [label, points] : plan.roofline) {
                Parameters p;
                p.device = device;
                p.resolution = plan.roofline_resolution;
                p.precision = precision == "float" ? Precision::Single : Precision::Double;
                const bool triad = device == devices.front().first && precision == o.precisions.front();
                std::fprintf(stderr, "[%zu/%zu] roofline %s on %s, %s\n", ++done, total, label.c_str(), device.c_str(), precision.c_str());
                keep(run_isolated([&] { return measure_roofline(label, points, p, o.quick ? 3 : 10, triad); }), "roofline", label, device,
                     precision);
            }
        }
    if (o.sections.count("quality")) run_quality(o, o.devices.empty() ? "auto" : devices.front().first, jsonl, records);
    if (o.sections.count("points")) run_points_section(o, jsonl, records);
    if (o.sections.count("tiles")) run_tiles_section(o, jsonl, records);
    if (o.sections.count("stages")) run_stages_section(o, jsonl, records);

    // Table 1: the paper's seconds where known.
    for (Record& r : records)
        if (r.text("section") == "table1" && r.text("case") == "bunny, every other point" && r.text("grid") == "256x256x224")
            r.set("paper_s", 167.32);

    const std::time_t now = std::time(nullptr);
    char when[64];
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    std::string heading = std::string("## snvr-bench") + (o.quick ? " --quick" : "") + ", " + when + "\n\nDevices:";
    for (const Record& r : found) heading += " " + r.text("device") + " (" + r.text("name") + ")";
    heading += ". Repetitions: " + std::to_string(o.repeat) +
               " after one warm-up (above 256 cells: one run, no warm-up); medians, (min-max) is the spread.";
    const std::string md = markdown(records, heading) + tiles_markdown(records) + stages_markdown(records);
    std::ofstream(o.out + "/results.md") << md;
    const std::string points_md = points_markdown(records);
    if (!points_md.empty()) std::ofstream(o.out + "/points.md") << heading << "\n" << points_md;
    write_plot_data(records, o.out);
    std::printf("%s", md.c_str());
    std::fprintf(stderr, "snvr-bench: wrote %s/results.jsonl, results.md and the plot data\n", o.out.c_str());
    return 0;
}
