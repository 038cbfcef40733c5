// snvr-bench --quick as CI runs it, so the suite cannot rot: it finishes, covers every
// device with every section, reports no failed case, measures the quality section's
// cases with both tools (or notes the peer is not built), runs the points section's
// tiny clouds through snvr-cl and the peers, the tiles section's one case and the stages
// section's (each stage's cost a unit beside its floor), and prints the tables it writes.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string field(const std::string& line, const std::string& key) {
    const std::string tag = "\"" + key + "\": \"";
    const std::size_t a = line.find(tag);
    if (a == std::string::npos) return "";
    const std::size_t b = line.find('"', a + tag.size());
    return line.substr(a + tag.size(), b - a - tag.size());
}

}  // namespace

TEST_CASE("snvr-bench --quick covers every device and section and prints its tables") {
    const fs::path out = fs::temp_directory_path() / ("snvr-bench-quick-" + std::to_string(::getpid()));
    fs::remove_all(out);
    const std::string cmd = std::string(SNVR_BENCH) + " --quick --out " + out.string() + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p != nullptr);
    std::string printed;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) printed.append(buf, n);
    const int status = pclose(p);
    CAPTURE(printed);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);

    std::ifstream jsonl(out / "results.jsonl");
    std::set<std::string> devices, seen, quality;
    int points_rows = 0, tiles_rows = 0, stages_rows = 0;
    std::string line;
    int records = 0;
    while (std::getline(jsonl, line)) {
        ++records;
        CAPTURE(line);
        CHECK(line.find("\"error\"") == std::string::npos);
        if (field(line, "section") == "quality") {
            // Runs once, not per device: a measured mesh or the peer's "not built" note.
            const bool measured = line.find("\"triangles\": ") != std::string::npos && line.find("\"inside_pct\": ") != std::string::npos;
            CHECK((measured || (field(line, "tool") == "openvdb" && field(line, "note").rfind("not built", 0) == 0)));
            if (!field(line, "png").empty()) {
                CHECK(fs::file_size(out / field(line, "png")) > 1000);
                CHECK(fs::file_size(out / field(line, "png_zoom")) > 1000);
            }
            quality.insert(field(line, "case") + " " + field(line, "tool"));
            continue;
        }
        if (field(line, "section") == "points") {
            // Once, not per device: snvr-cl, the distance peer and OpenVDB (or its note), none failed.
            ++points_rows;
            CHECK(line.find("_error\"") == std::string::npos);
            for (const char* key : {"\"snvr_process_s\": ", "\"snvr_peak_mib\": ", "\"snvr_steps_s\": ", "\"distance_mc_process_s\": ",
                                    "\"distance_mc_peak_mib\": ", "\"snvr_over_distance_mc_s\": "})
                CHECK(line.find(key) != std::string::npos);
            CHECK((line.find("\"openvdb_process_s\": ") != std::string::npos || field(line, "openvdb_note").rfind("not built", 0) == 0));
            continue;
        }
        if (field(line, "section") == "tiles") {
            // Once: the tiled run against the whole one, the same solid within 0.01 voxels.
            ++tiles_rows;
            CHECK(field(line, "same_solid") == "yes");
            CHECK(line.find("\"tiled_over_whole_s\": ") != std::string::npos);
            continue;
        }
        if (field(line, "section") == "stages") {
            // Once: every stage priced a unit, above its floor, beside OpenVDB (or its note).
            ++stages_rows;
            CHECK(line.find("_error\"") == std::string::npos);
            for (const char* key : {"\"triad_gbps\": ", "\"snvr_check_ns\": ", "\"snvr_check_floor_ns\": ", "\"snvr_steps_over_floor\": ",
                                    "\"snvr_init_units\": ", "\"snvr_mesh_floor_bytes\": ", "\"snvr_walls_on\": "})
                CHECK(line.find(key) != std::string::npos);
            CHECK((line.find("\"snvr_over_openvdb_s\": ") != std::string::npos || field(line, "openvdb_note").rfind("not built", 0) == 0));
            continue;
        }
        const std::string device = field(line, "device");
        if (field(line, "backend") != "host") devices.insert(device);
        seen.insert(field(line, "section") + " on " + device);
    }
    CHECK(records > 20);
    CHECK(devices.count("openmp") == 1);
    CHECK(devices.count("opencl:0:0") == 1);  // PoCL, which the set-up installs
    for (const std::string& d : devices)
        for (const char* s : {"table1", "table2", "roofline", "scaling"}) {
            CAPTURE(d);
            CAPTURE(s);
            CHECK(seen.count(std::string(s) + " on " + d) == 1);
        }
    for (const char* c : {"bunny snvr", "bunny openvdb", "sheets snvr", "sheets openvdb"}) {
        CAPTURE(c);
        CHECK(quality.count(c) == 1);
    }
    std::ifstream md_file(out / "results.md");
    std::stringstream md;
    md << md_file.rdbuf();
    CHECK(points_rows == 2);
    CHECK(tiles_rows == 1);
    CHECK(stages_rows == 1);
    for (const char* heading : {"### Paper's Table 1", "### Paper's Table 2", "### Roofline", "### Scaling", "### Quality", "### Points",
                                "### Tiles", "### Stages"}) {
        CHECK(md.str().find(heading) != std::string::npos);
        CHECK(printed.find(heading) != std::string::npos);
    }
    CHECK(md.str().find("### Not measured") == std::string::npos);
    for (const char* dat : {"scaling.dat", "roofline.dat", "table2.dat", "points.dat"}) CHECK(fs::file_size(out / dat) > 40);
    CHECK(fs::file_size(out / "points.md") > 200);
    fs::remove_all(out);
}
