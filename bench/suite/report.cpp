#include "report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <stdexcept>

#include "points_report.hpp"

namespace snvr::bench {

namespace {

std::vector<const Record*> section(const std::vector<Record>& all, const std::string& name) {
    std::vector<const Record*> out;
    for (const Record& r : all)
        if (r.text("section") == name && !r.has("error")) out.push_back(&r);
    return out;
}

std::string who(const Record& r) { return r.text("device") + " | " + r.text("precision"); }

// Bytes per cell of the band from a figure in MiB: memory against the surface's size.
double per_band_cell(const Record& r, const char* mib) { return r.number(mib) * double(1 << 20) / r.number("band_cells"); }

std::string seconds_with_spread(const Record& r) {
    return fmt("%.2f", r.number("total_s")) + " (" + fmt("%.2f", r.number("total_min_s")) + "-" + fmt("%.2f", r.number("total_max_s")) + ")";
}

// Observed order between this record and the previous one of the same shape, device
// and precision at a coarser grid: log(e_coarse / e_fine) / log(n_fine / n_coarse).
std::string order(const Record& fine, const Record* coarse, const char* key) {
    if (!coarse) return "-";
    return fmt("%.2f", std::log(coarse->number(key) / fine.number(key)) / std::log(fine.number("nx") / coarse->number("nx")));
}

std::string pair(const char* f, double a, double b) { return fmt(f, a) + ", " + fmt(f, b); }

// The quality section, errors and notes included: rows in run order (case,
// resolution, tool), then the previews.
std::string quality_table(const std::vector<Record>& all) {
    std::vector<const Record*> rows;
    for (const Record& r : all)
        if (r.text("section") == "quality") rows.push_back(&r);
    if (rows.empty()) return "";
    std::string md =
        "\n### Quality: libsnvr (snvr) and the OpenVDB peer at the same voxel h and offset l, judged by measure_quality\n\n"
        "Pieces: solids; genus over closed pieces; depth: points' depth inside the shell over l (min, 1st percentile); "
        "offset error: distance to the nearest point minus l, over h; dihedral and normal noise in degrees; wall: "
        "thickness over 2l (min, 1st percentile); exact: distance to the exact offset surface over h; s: reconstruction "
        "and meshing, seconds, one run (ours after a tiny run that loads the device's kernels).\n\n"
        "| case | cells | tool | grid | l (h) | pieces | cavities | genus | inside % | depth min, p1 (l) | offset error RMS, mean (h) | "
        "dihedral | normal noise | wall min, p1 (2l) | exact RMS, max (h) | triangles | s | note |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::string previews;
    for (const Record* r : rows) {
        md += "| " + r->text("case") + " | " + r->text("resolution") + " | " + r->text("tool") + " | ";
        if (r->has("error") || r->has("note")) {
            md += "| | | | | | | | | | | | | | | " + (r->has("error") ? "not measured: " + r->text("error") : r->text("note")) + " |\n";
            continue;
        }
        std::string note;
        if (r->text("closed") != "yes") note += "open; ";
        if (r->text("manifold") != "yes") note += "non-manifold; ";
        if (r->text("oriented") != "yes") note += "not oriented; ";
        if (r->number("open_components") > 0) note += r->text("open_components") + " open pieces; ";
        if (note.size() > 2) note.resize(note.size() - 2);
        md += r->text("grid") + " | " + fmt("%.2f", r->number("offset_h")) + " | " + r->text("solids") + " | " + r->text("cavities") + " | " +
              r->text("genus") + " | " + fmt("%.2f", r->number("inside_pct")) + " | " + pair("%.3f", r->number("depth_min_l"), r->number("depth_p01_l")) +
              " | " + pair("%.3f", r->number("offset_rms_h"), r->number("offset_mean_h")) + " | " + fmt("%.2f", r->number("dihedral_deg")) +
              " | " + fmt("%.2f", r->number("normal_noise_deg")) + " | " + pair("%.3f", r->number("wall_min_2l"), r->number("wall_p01_2l")) +
              " | " + (r->has("exact_rms_h") ? pair("%.3f", r->number("exact_rms_h"), r->number("exact_max_h")) : "-") + " | " +
              fmt("%.0f", r->number("triangles")) + " | " + fmt("%.2f", r->number("seconds")) + " | " + note + " |\n";
        if (r->has("png"))
            previews += "- " + r->text("case") + " at " + r->text("resolution") + " cells, " + r->text("tool") + ": [full](" + r->text("png") +
                        "), [3x zoom](" + r->text("png_zoom") + ")\n";
    }
    if (!previews.empty()) md += "\nPreviews (in this directory):\n\n" + previews;
    return md;
}

}  // namespace

std::string markdown(const std::vector<Record>& all, const std::string& heading) {
    std::string md = heading + "\n";
    const auto t1 = section(all, "table1");
    if (!t1.empty()) {
        md += "\n### Paper's Table 1: CPU seconds\n\n"
              "| case | device | precision | grid | points | steps | total s, median (min-max) | distance | init | steps | mesh | "
              "V-cycles | peak MiB | paper s | ours / paper |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (const Record* r : t1)
            md += "| " + r->text("case") + " | " + who(*r) + " | " + r->text("grid") + " | " + r->text("points") + " | " + r->text("steps") +
                  " | " + seconds_with_spread(*r) + " | " + fmt("%.2f", r->number("distance_s")) + " | " + fmt("%.2f", r->number("init_s")) +
                  " | " + fmt("%.2f", r->number("steps_s")) + " | " + fmt("%.2f", r->number("mesh_s")) + " | " + r->text("vcycles") + " | " +
                  fmt("%.0f", r->number("peak_rss_mib")) + " | " + fmt("%.2f", r->number("paper_s")) + " | " +
                  fmt("%.4f", r->number("total_s") / r->number("paper_s")) + " |\n";
    }
    const auto t2 = section(all, "table2");
    if (!t2.empty()) {
        md += "\n### Paper's Table 2: surface errors (RMS of distance - l over each sheet)\n\n"
              "| shape | device | precision | grid | steps | grown | paper | shrunk | paper | order (grown, shrunk) | total s |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n";
        std::map<std::string, const Record*> previous;  // shape, device, precision -> coarser result
        for (const Record* r : t2) {
            const std::string key = r->text("case") + "|" + who(*r);
            const Record* coarse = previous.count(key) ? previous[key] : nullptr;
            md += "| " + r->text("case") + " | " + who(*r) + " | " + r->text("grid") + " | " + r->text("steps") + " | " +
                  fmt("%.3e", r->number("grown")) + " | " + fmt("%.3e", r->number("paper_grown")) + " | " + fmt("%.3e", r->number("shrunk")) +
                  " | " + fmt("%.3e", r->number("paper_shrunk")) + " | " + order(*r, coarse, "grown") + ", " + order(*r, coarse, "shrunk") +
                  " | " + fmt("%.2f", r->number("total_s")) + " |\n";
            previous[key] = r;
        }
    }
    const auto rl = section(all, "roofline");
    if (!rl.empty()) {
        md += "\n### Roofline: achieved bandwidth against a copy on the same device\n\n"
              "| case | device | precision | kernel | ms, median (min-max) | GB moved | GB/s | of copy |\n|---|---|---|---|---|---|---|---|\n";
        for (const Record* r : rl) {
            if (r->has("floor_s"))
                md += "| " + r->text("case") + " | " + who(*r) + " | " + r->text("kernel") + " | " + fmt("%.3f s", r->number("steps_s")) +
                      " (floor " + fmt("%.3f s", r->number("floor_s")) + ") | " + fmt("%.2f", r->number("gb")) + " | | " +
                      fmt("%.0f%% of floor rate", 100 * r->number("of_floor")) + " |\n";
            else if (!r->has("ms"))
                md += "| " + r->text("case") + " | host | - | " + r->text("kernel") + " | | | " + fmt("%.1f", r->number("gbps")) + " | |\n";
            else
                md += "| " + r->text("case") + " | " + who(*r) + " | " + r->text("kernel") + " | " + fmt("%.2f", r->number("ms")) + " (" +
                      fmt("%.2f", r->number("ms_min")) + "-" + fmt("%.2f", r->number("ms_max")) + ") | " + fmt("%.3f", r->number("gb")) +
                      " | " + fmt("%.1f", r->number("gbps")) + " | " + fmt("%.0f%%", 100 * r->number("of_copy")) + " |\n";
        }
    }
    const auto sc = section(all, "scaling");
    if (!sc.empty()) {
        md += "\n### Scaling with resolution\n\n"
              "| case | device | precision | grid | cells | band cells | total s, median (min-max) | steps s | peak MiB | "
              "us per band cell | solver bytes per band cell | peak bytes per band cell |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (const Record* r : sc)
            md += "| " + r->text("case") + " | " + who(*r) + " | " + r->text("grid") + " | " + fmt("%.3g", r->number("cells")) + " | " +
                  fmt("%.3g", r->number("band_cells")) + " | " + seconds_with_spread(*r) + " | " + fmt("%.2f", r->number("steps_s")) + " | " +
                  fmt("%.0f", r->number("peak_rss_mib")) + " | " + fmt("%.2f", 1e6 * r->number("total_s") / r->number("band_cells")) + " | " +
                  fmt("%.1f", per_band_cell(*r, "solver_mib")) + " | " + fmt("%.1f", per_band_cell(*r, "peak_rss_mib")) + " |\n";
    }
    md += quality_table(all);
    md += points_markdown(all);
    std::string errors;
    for (const Record& r : all)
        if (r.has("error"))
            errors += "- " + r.text("section") + " " + r.text("case") +
                      (r.has("tool") ? " at " + r.text("resolution") + " cells, " + r.text("tool")
                                     : " on " + r.text("device") + " " + r.text("precision")) +
                      ": " + r.text("error") + "\n";
    if (!errors.empty()) md += "\n### Not measured\n\n" + errors;
    return md;
}

void write_plot_data(const std::vector<Record>& all, const std::string& dir) {
    const auto open = [&](const std::string& name) {
        std::ofstream f(dir + "/" + name);
        if (!f) throw std::runtime_error("cannot write " + dir + "/" + name);
        return f;
    };
    std::ofstream sc = open("scaling.dat");
    sc << "# series cells band_cells total_s steps_s peak_mib solver_bytes_per_band_cell peak_bytes_per_band_cell\n";
    for (const Record* r : section(all, "scaling"))
        sc << r->text("device") << "/" << r->text("precision") << ' ' << r->text("cells") << ' ' << r->text("band_cells") << ' '
           << r->text("total_s") << ' ' << r->text("steps_s") << ' ' << r->text("peak_rss_mib") << ' '
           << per_band_cell(*r, "solver_mib") << ' ' << per_band_cell(*r, "peak_rss_mib") << '\n';
    std::ofstream rl = open("roofline.dat");
    rl << "# series kernel gbps of_copy\n";
    for (const Record* r : section(all, "roofline"))
        if (r->has("of_copy")) {
            std::string kernel = r->text("kernel");
            for (char& c : kernel)
                if (c == ' ') c = '_';
            rl << r->text("device") << "/" << r->text("precision") << ' ' << kernel << ' ' << r->text("gbps") << ' ' << r->text("of_copy") << '\n';
        }
    write_points_data(all, dir);
    std::ofstream t2 = open("table2.dat");
    t2 << "# series n grown shrunk paper_grown paper_shrunk\n";
    for (const Record* r : section(all, "table2"))
        t2 << r->text("case") << "/" << r->text("device") << "/" << r->text("precision") << ' ' << r->text("nx") << ' ' << r->text("grown")
           << ' ' << r->text("shrunk") << ' ' << r->text("paper_grown") << ' ' << r->text("paper_shrunk") << '\n';
}

}  // namespace snvr::bench
