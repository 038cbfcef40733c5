#include "stages.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "host_measures.hpp"
#include "program_runs.hpp"

namespace snvr::bench {

namespace {

namespace fs = std::filesystem;

// The stages the report prices by a unit, in the run's order.
const char* const kStages[] = {"distance", "init", "steps", "mesh", "check", "write"};

struct StageCase {
    std::string scan;
    int cells = 0;
};

StageCase parse_case(const std::string& text) {
    const std::size_t at = text.find('@');
    if (at == std::string::npos || std::atoi(text.c_str() + at + 1) < 32)
        throw std::runtime_error("a stages case is SCAN@CELLS (at least 32 cells), got '" + text + "'");
    return {text.substr(0, at), std::atoi(text.c_str() + at + 1)};
}

// Each stage's floor a unit: its bytes at the triad's rate, in nanoseconds.
void set_floors(Record& r, double gbps) {
    for (const char* stage : kStages) {
        const std::string key = std::string("snvr_") + stage;
        if (!r.has(key + "_ns") || !(r.number(key + "_units") > 0)) continue;
        const double floor_ns = r.number(key + "_floor_bytes") / r.number(key + "_units") / gbps;
        r.set(key + "_floor_ns", floor_ns).set(key + "_over_floor", r.number(key + "_ns") / floor_ns);
    }
}

}  // namespace

void run_stages(const StagesOptions& o, const std::string& snvr_cl, const std::string& openvdb_peer,
                const std::function<void(const Record&)>& keep) {
    std::vector<std::string> cases = o.cases;
    if (cases.empty()) cases = o.quick ? std::vector<std::string>{"bunny@96"} : std::vector<std::string>{"bunny@256", "bunny@1024"};
    const int pairs = o.quick ? 1 : o.repeat;
    const std::string dir = o.scratch + "/run";
    fs::create_directories(dir);
    // The stream rate both cores reach, as the stages run on both.
    const double gbps = triad_bandwidth() / 1e9;
    // The first run on a device builds its kernels (then cached): not in a measured run.
    Lengths unused;
    Record warm;
    measure_ours(snvr_cl, o.device, o.data + "/bunny.ply", 32, dir, warm, unused);
    for (const std::string& text : cases) {
        Record base;
        base.set("section", "stages").set("case", text).set("device", o.device.empty() ? "auto" : o.device);
        try {
            const StageCase c = parse_case(text);
            const std::string cloud = o.data + "/" + c.scan + ".ply";
            if (!fs::exists(cloud)) throw std::runtime_error("no scan " + cloud);
            for (int k = 0; k < pairs; ++k) {
                std::fprintf(stderr, "[stages] %s, pair %d of %d\n", text.c_str(), k + 1, pairs);
                Record r = base;
                r.set("resolution", c.cells).set("pair", k + 1).set("triad_gbps", gbps);
                Lengths lengths;
                if (measure_ours(snvr_cl, o.device, cloud, c.cells, dir, r, lengths)) {
                    set_floors(r, gbps);
                    measure_openvdb_peer(openvdb_peer, cloud, lengths, dir, r);
                    if (r.has("openvdb_process_s") && !r.has("openvdb_error"))
                        r.set("snvr_over_openvdb_s", r.number("snvr_process_s") / r.number("openvdb_process_s"));
                }
                for (const char* out : {"snvr.stl", "snvr.json", "openvdb.stl"}) fs::remove(dir + "/" + out);
                keep(r);
            }
        } catch (const std::exception& e) {
            keep(base.set("error", e.what()));
        }
    }
    std::error_code ignored;
    fs::remove_all(o.scratch, ignored);
}

std::string stages_markdown(const std::vector<Record>& all) {
    std::vector<const Record*> rows;
    for (const Record& r : all)
        if (r.text("section") == "stages" && !r.has("error") && !r.has("snvr_error")) rows.push_back(&r);
    if (rows.empty()) return "";
    std::string md =
        "\n### Stages: each by its unit of work, beside its floor and the OpenVDB peer\n\n"
        "snvr-cl reconstruct, then the OpenVDB peer at its voxel and offset, in turn, whole processes (wall seconds). "
        "ns a unit: the stage's seconds over its band cells (steps: band cells x steps) or the shell's triangles; floor: "
        "the bytes it must touch at the least (the report's per_unit) at the OpenMP triad's rate taken at the section's "
        "start.\n\n"
        "| case | pair | ours s | OpenVDB s | ours / OpenVDB | triad GB/s |";
    for (const char* stage : kStages) md += std::string(" ") + stage + " s, ns a unit (floor) |";
    md += "\n|---|---|---|---|---|---|";
    for (std::size_t k = 0; k < std::size(kStages); ++k) md += "---|";
    md += "\n";
    for (const Record* r : rows) {
        md += "| " + r->text("case") + " | " + fmt("%.0f", r->number("pair")) + " | " + fmt("%.2f", r->number("snvr_process_s")) +
              " | " + fmt("%.2f", r->number("openvdb_process_s")) + " | **" + fmt("%.2f", r->number("snvr_over_openvdb_s")) +
              "** | " + fmt("%.1f", r->number("triad_gbps")) + " |";
        for (const char* stage : kStages) {
            const std::string key = std::string("snvr_") + stage;
            md += " " + fmt("%.2f", r->number(key + "_s")) + ", " + fmt("%.3g", r->number(key + "_ns")) + " (" +
                  fmt("%.2g", r->number(key + "_floor_ns")) + ") |";
        }
        md += "\n";
    }
    return md;
}

}  // namespace snvr::bench
