#include "program_runs.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

namespace snvr::bench {

using nlohmann::json;

std::string exact(double v) {
    char s[40];
    std::snprintf(s, sizeof s, "%.17g", v);
    return s;
}

bool measure_ours(const std::string& snvr_cl, const std::string& device, const std::string& cloud, int grid,
                  const std::string& dir, Record& r, Lengths& lengths) {
    const std::string report = dir + "/snvr.json";
    std::vector<std::string> argv{snvr_cl, "reconstruct", cloud, "-o", dir + "/snvr.stl", "--resolution", std::to_string(grid),
                                  "--report", report, "--quiet"};
    if (!device.empty()) argv.insert(argv.end(), {"--device", device});
    const ProgramRun run = run_program(argv);
    r.set("snvr_process_s", run.seconds).set("snvr_cpu_s", run.cpu_seconds).set("snvr_peak_mib", run.peak_mib);
    if (!run.ok()) {
        r.set("snvr_error", run.why());
        return false;
    }
    try {
        std::ifstream in(report);
        const json rep = json::parse(in);
        // The report's lengths are in millimetres; the peers take the input's units.
        const double to_input = 1 / rep.at("input").at("to_millimetres").get<double>();
        lengths.voxel = rep.at("grid").at("voxel").get<double>() * to_input;
        lengths.offset = rep.at("offset").at("length").get<double>() * to_input;
        const json& g = rep.at("grid");
        const double dropped = rep.at("outliers").at("dropped").get<double>();
        r.set("points", rep.at("input").at("points").get<double>() + dropped).set("outliers_dropped", dropped);
        r.set("grid", std::to_string(g.at("nx").get<int>()) + "x" + std::to_string(g.at("ny").get<int>()) + "x" +
                          std::to_string(g.at("nz").get<int>()));
        r.set("voxel", lengths.voxel).set("offset", lengths.offset).set("offset_h", lengths.offset / lengths.voxel);
        r.set("band_cells", g.at("active_cells").get<double>()).set("backend", rep.at("backend").get<std::string>());
        for (const char* stage : {"read", "outliers", "domain", "distance", "init", "steps", "mesh", "write", "check", "total"})
            r.set(std::string("snvr_") + stage + "_s", rep.at("seconds").at(stage).get<double>());
        r.set("snvr_triangles", rep.at("mesh").at("triangles").get<double>());
        r.set("snvr_walls_on", rep.at("check").at("walls_on").get<std::string>());
        for (const auto& [stage, u] : rep.at("per_unit").items()) {
            const std::string key = "snvr_" + stage;
            r.set(key + "_ns", u.at("ns").get<double>()).set(key + "_units", u.at("units").get<double>());
            r.set(key + "_floor_bytes", u.at("floor_bytes").get<double>()).set(key + "_unit", u.at("unit").get<std::string>());
        }
    } catch (const std::exception& e) {
        r.set("snvr_error", std::string("reading its report: ") + e.what());
        return false;
    }
    return true;
}

std::optional<ProgramRun> run_peer(const std::string& name, const std::string& program, const std::string& cloud,
                                   const Lengths& l, const std::string& dir, Record& r) {
    ProgramRun run = run_program({program, cloud, "-o", dir + "/" + name + ".stl", "--voxel", exact(l.voxel), "--offset",
                                  exact(l.offset)});
    r.set(name + "_process_s", run.seconds).set(name + "_cpu_s", run.cpu_seconds).set(name + "_peak_mib", run.peak_mib);
    if (!run.ok()) {
        r.set(name + "_error", run.why());
        return std::nullopt;
    }
    return run;
}

void measure_openvdb_peer(const std::string& program, const std::string& cloud, const Lengths& l, const std::string& dir,
                          Record& r) {
    if (program.empty()) {
        r.set("openvdb_note", "not built (needs libopenvdb-dev and libboost-dev at configure time)");
        return;
    }
    const std::optional<ProgramRun> run = run_peer("openvdb", program, cloud, l, dir, r);
    if (!run) return;
    const std::size_t at = run->output.find("triangles ");
    if (at != std::string::npos) r.set("openvdb_triangles", std::atof(run->output.c_str() + at + 10));
}

}  // namespace snvr::bench
