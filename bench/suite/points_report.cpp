#include "points_report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <stdexcept>

namespace snvr::bench {

namespace {

std::string joined(const std::vector<std::string>& parts) {
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : ", ") + p;
    return out;
}

std::vector<const Record*> points_rows(const std::vector<Record>& all) {
    std::vector<const Record*> out;
    for (const Record& r : all)
        if (r.text("section") == "points") out.push_back(&r);
    return out;
}

// The programs as the tables and the plot name them.
struct Program {
    const char* key;    // the records' prefix
    const char* label;  // the tables' and the plot's
};
constexpr Program kPrograms[] = {{"snvr", "snvr-cl"}, {"distance_mc", "distance+MC"}, {"openvdb", "OpenVDB"}};

bool measured(const Record& r, const std::string& p) { return r.has(p + "_process_s") && !r.has(p + "_error"); }

// Wall-clock seconds, and CPU seconds in brackets.
std::string seconds(const Record& r, const std::string& p) {
    return measured(r, p) ? fmt("%.2f", r.number(p + "_process_s")) + " (" + fmt("%.2f", r.number(p + "_cpu_s")) + ")" : "-";
}
std::string mib(const Record& r, const std::string& p) { return measured(r, p) ? fmt("%.0f", r.number(p + "_peak_mib")) : "-"; }

}  // namespace

std::string points_markdown(const std::vector<Record>& all) {
    const std::vector<const Record*> rows = points_rows(all);
    if (rows.empty()) return "";
    std::set<std::string> backends;
    for (const Record* r : rows)
        if (r->has("backend")) backends.insert(r->text("backend"));
    std::string ran_on;
    for (const std::string& b : backends) ran_on += (ran_on.empty() ? "" : ", ") + b;
    std::string md =
        "\n### Points: the cost of a run against the number of points\n\n"
        "Each program a process of its own: its wall-clock seconds and peak resident memory (wait4), file to mesh; a program "
        "whose first run took under 10 s runs --repeat times (the median run; its spread in results.jsonl), the others once. "
        "snvr-cl reconstruct at the grid (cells on the longest axis, its defaults otherwise; on " +
        (ran_on.empty() ? std::string("-") : ran_on) +
        "); the plain distance + marching cubes peer (distance+MC) and OpenVDB (particles to level set, 4 curvature steps, "
        "volume to mesh) at its voxel h and offset l. ns per extra point: (t(N) - t(N0)) / (N - N0) against the same shape's "
        "smallest cloud at the same grid, of wall-clock and of CPU seconds (user + system, every thread: on a shared "
        "machine the steadier figure). s (cpu): wall-clock seconds (CPU seconds); ratios of wall-clock seconds.\n\n"
        "| cloud | points | grid | l (h) | snvr-cl s (cpu) | MiB | distance+MC s (cpu) | MiB | OpenVDB s (cpu) | MiB | "
        "snvr-cl / distance+MC: s, MiB | snvr-cl / OpenVDB: s, MiB | ns per extra point, wall: snvr-cl, distance+MC, OpenVDB | "
        "the same, cpu |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::string problems;
    for (const Record* r : rows) {
        md += "| " + r->text("case") + " | " + fmt("%.0f", r->number("points")) + " | " + r->text("resolution") + " | " +
              fmt("%.2f", r->number("offset_h"));
        for (const Program& p : kPrograms) md += " | " + seconds(*r, p.key) + " | " + mib(*r, p.key);
        for (const char* peer : {"distance_mc", "openvdb"})
            md += " | " + fmt("%.2f", r->number(std::string("snvr_over_") + peer + "_s")) + ", " +
                  fmt("%.2f", r->number(std::string("snvr_over_") + peer + "_mib"));
        std::vector<std::string> wall, cpu;
        for (const Program& p : kPrograms) {
            wall.push_back(fmt("%.0f", r->number(std::string(p.key) + "_ns_per_point")));
            cpu.push_back(fmt("%.0f", r->number(std::string(p.key) + "_cpu_ns_per_point")));
        }
        md += " | " + joined(wall) + " | " + joined(cpu) + " |\n";
        if (r->has("error")) problems += "- " + r->text("case") + " at " + r->text("resolution") + ": " + r->text("error") + "\n";
        for (const Program& p : kPrograms)
            if (r->has(std::string(p.key) + "_error"))
                problems += "- " + r->text("case") + " at " + r->text("resolution") + ", " + p.label + ": " +
                            r->text(std::string(p.key) + "_error") + "\n";
        if (r->has("openvdb_note") && problems.find("OpenVDB: not built") == std::string::npos)
            problems += "- OpenVDB: " + r->text("openvdb_note") + "\n";
    }
    md += "\nOur stages (snvr-cl --report, seconds) and the peer's (index: the kd-tree; band: finding the band's cells):\n\n"
          "| cloud | points | grid | band cells | read | outliers | domain | distance | init | steps | mesh | write | check | total | "
          "distance+MC: read, index, band, distance, mesh |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Record* r : rows) {
        md += "| " + r->text("case") + " | " + fmt("%.0f", r->number("points")) + " | " + r->text("grid") + " | " +
              fmt("%.3g", r->number("band_cells"));
        for (const char* stage : {"read", "outliers", "domain", "distance", "init", "steps", "mesh", "write", "check", "total"})
            md += " | " + fmt("%.2f", r->number(std::string("snvr_") + stage + "_s"));
        std::vector<std::string> peer_stages;
        for (const char* stage : {"read", "index", "band", "distance", "mesh"})
            peer_stages.push_back(fmt("%.2f", r->number(std::string("distance_mc_") + stage + "_s")));
        md += " | " + joined(peer_stages) + " |\n";
    }
    if (!problems.empty()) md += "\nNot measured:\n\n" + problems;
    return md;
}

void write_points_data(const std::vector<Record>& all, const std::string& dir) {
    std::ofstream f(dir + "/points.dat");
    if (!f) throw std::runtime_error("cannot write " + dir + "/points.dat");
    f << "# series family points seconds peak_mib cpu_seconds\n";
    for (const Program& p : kPrograms)
        for (const Record* r : points_rows(all))
            if (measured(*r, p.key))
                f << p.label << "/" << r->text("resolution") << ' ' << r->text("family") << ' ' << r->text("points") << ' '
                  << r->text(std::string(p.key) + "_process_s") << ' ' << r->text(std::string(p.key) + "_peak_mib") << ' '
                  << r->text(std::string(p.key) + "_cpu_s") << '\n';
}

}  // namespace snvr::bench
