#include "tiles.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "snvr/mesh_io.hpp"
#include "snvr/quality.hpp"
#include "spawn.hpp"

namespace snvr::bench {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct TileCase {
    std::string cloud;
    int cells = 0, tile = 0;
};

TileCase parse_case(const std::string& text) {
    const std::size_t at = text.find('@'), slash = text.find('/', at == std::string::npos ? 0 : at);
    if (at == std::string::npos || slash == std::string::npos)
        throw std::runtime_error("a tiles case is CLOUD@CELLS/TILE, got '" + text + "'");
    return {text.substr(0, at), std::atoi(text.substr(at + 1, slash - at - 1).c_str()), std::atoi(text.substr(slash + 1).c_str())};
}

ProgramRun must_run(const std::vector<std::string>& argv) {
    ProgramRun run = run_program(argv);
    if (!run.ok()) throw std::runtime_error(argv[0] + " " + argv[1] + ": " + run.why());
    return run;
}

// The cloud's file: a scan of the data folder, else the sampler's shape (NAME or NAME-SPACING) made in scratch.
std::string cloud_file(const TilesOptions& o, const std::string& snvr_cl, const std::string& cloud) {
    const std::string scan = o.data + "/" + cloud + ".ply";
    if (fs::exists(scan)) return scan;
    const std::string made = o.scratch + "/" + cloud + ".ply";
    if (fs::exists(made)) return made;
    std::vector<std::string> argv{snvr_cl, "sample"};
    const std::size_t dash = cloud.find_last_of('-');
    const bool spaced = dash != std::string::npos && std::isdigit(static_cast<unsigned char>(cloud[dash + 1]));
    argv.push_back(spaced ? cloud.substr(0, dash) : cloud);
    if (spaced) argv.insert(argv.end(), {"--spacing", cloud.substr(dash + 1)});
    argv.insert(argv.end(), {"-o", made});
    must_run(argv);
    return made;
}

json report_of(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("no report at " + path);
    return json::parse(in);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

Record measure(const TilesOptions& o, const std::string& snvr_cl, const TileCase& c) {
    const std::string input = cloud_file(o, snvr_cl, c.cloud);
    const auto argv = [&](const std::string& name, int tile) {
        std::vector<std::string> a{snvr_cl, "reconstruct", input, "-o", o.scratch + "/" + name + ".stl", "--resolution",
                                   std::to_string(c.cells), "--report", o.scratch + "/" + name + ".json", "--quiet"};
        if (tile) a.insert(a.end(), {"--tile-cells", std::to_string(tile)});
        if (!o.device.empty()) a.insert(a.end(), {"--device", o.device});
        return a;
    };
    std::vector<double> whole_s, tiled_s, ratio, whole_cpu, tiled_cpu, whole_mib, tiled_mib;
    for (int r = 0; r < (o.quick ? 1 : o.repeat); ++r) {
        const ProgramRun w = must_run(argv("whole", 0)), t = must_run(argv("tiled", c.tile));
        whole_s.push_back(w.seconds);
        tiled_s.push_back(t.seconds);
        ratio.push_back(t.seconds / w.seconds);
        whole_cpu.push_back(w.cpu_seconds);
        tiled_cpu.push_back(t.cpu_seconds);
        whole_mib.push_back(w.peak_mib);
        tiled_mib.push_back(t.peak_mib);
    }
    const json whole = report_of(o.scratch + "/whole.json"), tiled = report_of(o.scratch + "/tiled.json");
    const double h = whole["grid"]["voxel"].get<double>();
    const VertexDistance d = vertex_distance(read_mesh(o.scratch + "/whole.stl"), read_mesh(o.scratch + "/tiled.stl"));
    const json& wc = whole["check"];
    const json& tc = tiled["check"];
    const bool same = wc["genus"] == tc["genus"] && wc["solids"] == tc["solids"] && wc["components"] == tc["components"] &&
                      wc["points_inside"] == tc["points_inside"];
    const json& tiles = tiled["tiles"];
    Record rec;
    rec.set("section", "tiles").set("case", c.cloud).set("points", whole["input"]["points"].get<double>())
        .set("resolution", double(c.cells)).set("tile_cells", double(c.tile))
        .set("halo_cells", tiles["halo_cells"].get<double>()).set("tiles", tiles["count"].get<double>())
        .set("tiles_run", tiles["run"].get<double>()).set("reruns", tiles["reruns"].get<double>())
        .set("cells_run_over_cores", tiles["cells_run_over_cores"].get<double>())
        .set("whole_s", median(whole_s)).set("tiled_s", median(tiled_s)).set("tiled_over_whole_s", median(ratio))
        .set("whole_cpu_s", median(whole_cpu)).set("tiled_cpu_s", median(tiled_cpu))
        .set("whole_peak_mib", median(whole_mib)).set("tiled_peak_mib", median(tiled_mib))
        .set("whole_solver_mib", whole["memory"]["solver_bytes"].get<double>() / 1048576)
        .set("tiled_solver_mib", tiled["memory"]["solver_bytes"].get<double>() / 1048576)
        .set("whole_steps_s", whole["seconds"]["steps"].get<double>()).set("tiled_steps_s", tiled["seconds"]["steps"].get<double>())
        .set("max_vertex_voxels", d.max / h).set("rms_vertex_voxels", d.rms / h)
        .set("same_solid", same ? "yes" : "no").set("genus", wc["genus"].get<double>());
    return rec;
}

}  // namespace

void run_tiles(const TilesOptions& options, const std::string& snvr_cl, const std::function<void(const Record&)>& keep) {
    std::vector<std::string> cases = options.cases;
    if (cases.empty())
        cases = options.quick ? std::vector<std::string>{"bunny@128/64"}
                              : std::vector<std::string>{"bunny@256/128", "bunny@512/128", "lidar@256/64"};
    fs::create_directories(options.scratch);
    for (const std::string& text : cases) {
        std::fprintf(stderr, "tiles %s\n", text.c_str());
        try {
            keep(measure(options, snvr_cl, parse_case(text)));
        } catch (const std::exception& e) {
            keep(Record().set("section", "tiles").set("case", text).set("error", e.what()));
        }
    }
    std::error_code ignored;
    fs::remove_all(options.scratch, ignored);
}

std::string tiles_markdown(const std::vector<Record>& all) {
    std::string rows;
    for (const Record& r : all) {
        if (r.text("section") != "tiles" || r.has("error")) continue;
        rows += "| " + r.text("case") + " | " + fmt("%.0f", r.number("points")) + " | " + fmt("%.0f", r.number("resolution")) +
                " | " + fmt("%.0f", r.number("tile_cells")) + " + " + fmt("%.0f", r.number("halo_cells")) + " | " +
                fmt("%.0f", r.number("tiles_run")) + " of " + fmt("%.0f", r.number("tiles")) + " | " +
                fmt("%.2f", r.number("cells_run_over_cores")) + " | " + fmt("%.2f", r.number("whole_s")) + " / " +
                fmt("%.2f", r.number("tiled_s")) + " | **" + fmt("%.2f", r.number("tiled_over_whole_s")) + "** | " +
                fmt("%.2f", r.number("whole_steps_s")) + " / " + fmt("%.2f", r.number("tiled_steps_s")) + " | " +
                fmt("%.0f", r.number("whole_peak_mib")) + " / " + fmt("%.0f", r.number("tiled_peak_mib")) + " | " +
                fmt("%.1f", r.number("whole_solver_mib")) + " / " + fmt("%.1f", r.number("tiled_solver_mib")) + " | " +
                fmt("%.2g", r.number("max_vertex_voxels")) + " / " + fmt("%.2g", r.number("rms_vertex_voxels")) + " | " +
                r.text("same_solid") + " |\n";
    }
    if (rows.empty()) return "";
    return "\n### Tiles: a run cut into tiles against the same run whole\n\n"
           "snvr-cl reconstruct at the grid, whole and with --tile-cells (core + the halo derived from the flow), in turn; "
           "seconds and peak memory of the whole process (median of the pairs; the ratio is the median of the pairs' "
           "ratios), steps and the solver's fields from --report; vertex distance: from each vertex of either mesh to the "
           "other's nearest, in voxels (max / RMS); same solid: pieces, genus and points inside alike.\n\n"
           "| cloud | points | grid | tile + halo | tiles run | cells run / cores | s whole / tiled | tiled / whole | "
           "steps s | peak MiB | solver MiB | vertex distance max / RMS | same solid |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n" +
           rows;
}

}  // namespace snvr::bench
