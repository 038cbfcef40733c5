// snvr-cl reconstruct: read, reconstruct, mesh, check, write, report.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <system_error>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "processes.hpp"
#include "report.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "snvr/tiles.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/render.hpp"
#include "snvr/report.hpp"
#include "snvr/shell.hpp"
#include "snvr/stopwatch.hpp"

namespace cli {
namespace {

using snvr::Stopwatch;

// Fails before a long run rather than after it when an output cannot be written.
void check_writable_location(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw snvr::IoError("cannot write '" + path + "': it is a directory");
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    if (!fs::is_directory(dir, ec))
        throw snvr::IoError("cannot write '" + path + "': directory '" + dir.string() + "' does not exist");
}

// The user's files are never outputs: an output that is the input (the same path, or
// reached through a symbolic or hard link) is refused before anything runs.
void refuse_overwriting_input(const std::string& input, const std::string& output, const char* which) {
    std::error_code ec;
    if (std::filesystem::equivalent(input, output, ec))
        throw snvr::IoError("refusing to write " + std::string(which) + " '" + output + "': it is the input '" +
                            input + "'; choose another output file");
}

// Whether two output paths name one file: the same file already (any link), or the
// same path once made absolute with its existing folders' links and any . and .. resolved.
bool same_file(const std::string& a, const std::string& b) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::equivalent(a, b, ec)) return true;
    const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec);
    if (ec) return false;
    const fs::path cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
    return !ec && ca == cb;
}

// Every output, before the long run: its folder there, not the input, and no two of
// them one file (the later would replace the earlier).
void check_outputs(const ReconstructOptions& o) {
    struct Output {
        std::string path;
        const char* option;
        const char* which;
    };
    std::vector<Output> outputs;
    for (const Output& out : {Output{o.output, "-o", "the mesh"}, Output{o.volume, "--volume", "the volume"},
                              Output{o.report, "--report", "the report"}, Output{o.outliers, "--outliers", "the outliers"},
                              Output{o.preview, "--preview", "the preview"}}) {
        if (out.path.empty()) continue;
        for (const Output& earlier : outputs)
            if (same_file(out.path, earlier.path))
                throw UsageError(std::string(earlier.option) + " '" + earlier.path + "' and " + out.option + " '" +
                                 out.path + "' name one file: give each output a file of its own");
        outputs.push_back(out);
    }
    for (const Output& out : outputs) {
        check_writable_location(out.path);
        refuse_overwriting_input(o.input, out.path, out.which);
    }
    // The temporary folder (--temp-dir, else the output's own) before the long run.
    const std::string& temp = o.shell.params.temp_dir;
    std::error_code ec;
    if (!std::filesystem::is_directory(temp, ec))
        throw snvr::IoError("the temporary folder '" + temp + "' (--temp-dir) is not a directory");
    if (::access(temp.c_str(), W_OK | X_OK) != 0)
        throw snvr::IoError("cannot write temporary files in '" + temp + "' (--temp-dir, by default the output's folder): " +
                            std::strerror(errno));
}

// Errors about the points name the input too (a file's own errors name their file).
[[noreturn]] void rethrow_naming_input(const std::string& input) {
    try {
        throw;
    } catch (const snvr::IoError&) {
        throw;
    } catch (const snvr::InputError& e) {
        throw snvr::InputError(input + ": " + e.what());
    } catch (const snvr::ParameterError& e) {
        throw snvr::ParameterError(input + ": " + e.what());
    } catch (const snvr::ResourceError& e) {
        throw snvr::ResourceError(input + ": " + e.what());
    }
}

}  // namespace

int run_reconstruct(const std::vector<std::string>& args) {
    std::optional<ReconstructOptions> parsed = parse_reconstruct(args, process_rank() == 0 ? std::cout : std::cerr);
    if (!parsed) return 0;
    // Under MPI the processes share the tiles; the first meshes, writes and reports.
    if (process_count() > 1 && parsed->shell.params.tile_cells == 0)
        throw UsageError("under an MPI launcher (" + std::to_string(process_count()) +
                         " processes) give --tile-cells N: the processes share a tiled run's tiles");
    parsed->shell.tiles_on = process_tiles();
    // The others read nothing: the first gives each its plan, its tiles and their points.
    if (process_rank() != 0) {
        // Its part of filing the points, its tiles, then its share of the check: the walls
        // and points of its tiles.
        snvr::serve_input(parsed->input, parsed->shell.params, *parsed->shell.tiles_on);
        snvr::serve_shell(parsed->shell.params, *parsed->shell.tiles_on);
        return 0;
    }
    const ReconstructOptions& o = *parsed;
    const auto say = [&o](const std::string& line) {
        if (!o.quiet) std::cerr << snvr::printable(line) << std::endl;
    };

    Stopwatch total, stage;
    check_outputs(o);
    const snvr::ShellSettings& settings = o.shell;
    snvr::RunFiles files;
    files.input = o.input;

    say("read: " + o.input);
    snvr::InputPoints input = snvr::read_input(o.input, settings.params, settings.tiles_on.get());
    files.read_seconds = stage.lap();
    if (input.triangles)
        say(snvr::format_text("read: a mesh of %s triangles, sampled at %.3g into %s points",
                              grouped(input.triangles).c_str(), input.spacing, grouped(input.points.size()).c_str()));
    else
        say("read: " + grouped(input.points.size()) + " points");
    try {
        // Staged first (whole files, not yet visible), then renamed into place together:
        // a failure anywhere leaves every output as it was, and a written output always
        // means exit 0 (the checks only warn). The mesh is staged as soon as it is final,
        // while the check runs (over several processes, the others measure meanwhile).
        snvr::OutputFiles outputs;
        snvr::ShellSettings run_settings = settings;
        // The mesh streamed into its file as it comes (over several processes a slab at a
        // time, none holding it whole), where the format takes it so and no preview needs
        // it whole.
        if (o.preview.empty()) run_settings.mesh_sink = outputs.mesh_sink(o.output);
        if (!run_settings.mesh_sink)
            run_settings.mesh_ready = [&](const snvr::Mesh& mesh) {
                say("write: " + o.output);
                files.outputs.push_back({o.output, "mesh", outputs.add_mesh(mesh, o.output)});
            };
        // A stage's parts and how far it has come: a line every few seconds at most
        // (the bunny's mesh stage tells four parts in 0.3 s); what it did, always.
        ProgressPace pace;
        snvr::Shell shell = snvr::make_shell(std::move(input.points), run_settings, [&](const snvr::Progress& p) {
            if (p.stage == "outliers" && p.outcome)
                say(snvr::format_text("outliers: %s (sparse, lone points standing off the surface, or in clusters of "
                                      "under %zu points apart by over 2 x offset); --keep-outliers keeps them",
                                      p.message.c_str(), settings.outliers.min_cluster));
            else if (p.stage == "check" && p.message.empty()) say("check: the shell against the points");
            else if (p.message.empty() && (p.stage == "outliers" || p.stage == "mesh")) {
            }  // their parts say what they do
            else if (!o.quiet && pace.due(p)) print_progress(std::cerr, p);
            return true;
        });
        stage.lap();  // make_shell timed its own stages
        if (shell.run.tiles.worker) return 0;  // its tiles are the first process's now
        if (run_settings.mesh_sink) {  // written as it came
            say("write: " + o.output);
            files.outputs.push_back({o.output, "mesh", outputs.staged_bytes(o.output)});
        }
        const snvr::Result& result = shell.run;
        for (const std::string& w : shell.warnings) warn(w);

        if (!o.volume.empty()) {
            say("write: " + o.volume);
            files.outputs.push_back({o.volume, "volume", outputs.add_field(result.phi, result.domain, o.volume)});
        }
        if (!o.outliers.empty()) {  // where the kept points went: shifted alike
            snvr::PointSet dropped = shell.outliers.points;
            for (snvr::Vec3& p : dropped)
                for (int a = 0; a < 3; ++a) p[a] -= shell.shift[a];
            outputs.add_points(dropped, o.outliers, "outliers dropped by snvr-cl");
            files.outliers_file = o.outliers;
        }
        if (!o.preview.empty()) outputs.add_bytes(snvr::render::preview_png(shell.mesh, o.preview), o.preview);
        files.write_seconds = shell.seconds.mesh_ready + stage.lap();
        files.total_seconds = total.lap();
        const snvr::RunReport report = snvr::make_report(shell, files);
        if (!o.report.empty()) outputs.add_bytes(snvr::report_json(report), o.report);
        outputs.commit();
        if (!o.quiet) std::cerr << "summary:\n" << snvr::report_summary(report) << std::flush;
        return 0;
    } catch (...) {
        rethrow_naming_input(o.input);
    }
}

}  // namespace cli
