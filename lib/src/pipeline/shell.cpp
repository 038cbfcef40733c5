// make_shell (shell.hpp): the job snvr-cl runs, in the order it runs it. Each stage
// tells the progress callback first, so that a cancel stops before the next one.
#include "snvr/shell.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <new>
#include <optional>
#include <string>
#include <utility>

#include "geometry/point_tree.hpp"
#include "check/walls.hpp"
#include "devices/check_device.hpp"
#include "geometry/vec3_math.hpp"
#include "io/formats.hpp"
#include "pipeline/outlier_policy.hpp"
#include "pipeline/shared_check.hpp"
#include "solver/plan_guard.hpp"
#include "pipeline/shared_guard.hpp"
#include "pipeline/shell_mesh.hpp"
#include "pipeline/slab_handover.hpp"
#include "process_limits.hpp"
#include "spilled_memory.hpp"
#include "told_pace.hpp"
#include "solver/memory_budget.hpp"
#include "solver/shared_filing.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/report.hpp"
#include "snvr/stopwatch.hpp"

namespace snvr {
namespace {

// The file name written_as stands for: a bare extension names a file of that format.
std::string written_file(const std::string& written_as) {
    return !written_as.empty() && written_as[0] == '.' ? "shell" + written_as : written_as;
}

// Survey scans arrive far from the origin and slicers ignore absolute placement: a print
// format (STL, 3MF) is centred where its float32 would otherwise move the shell (the
// run's voxel taken at its smallest, the points' box over the resolution; the shell
// reaches an offset beyond the points). PLY is not a print format and is kept. The points
// and the lengths are in their units; to_mm takes them to the millimetres written.
bool print_format_needs_centring(const std::string& written_as, const PointCloud& points, const Parameters& params,
                                 double to_mm) {
    const std::string as = written_file(written_as);
    if (!detail::is_print_format(as) || points.empty()) return false;
    const std::array<Vec3, 2> box = points.box();
    double longest = 0, farthest = 0;
    for (int a = 0; a < 3; ++a) {
        longest = std::max(longest, (box[1][a] - box[0][a]) * to_mm);
        farthest = std::max({farthest, std::abs(box[0][a]) * to_mm, std::abs(box[1][a]) * to_mm});
    }
    const double voxel = params.voxel ? *params.voxel * to_mm : longest / params.resolution;
    const double offset = params.offset      ? *params.offset * to_mm
                          : params.thickness ? *params.thickness * to_mm / 2
                                             : 3 * voxel;
    return voxel > 0 && !holds_faithfully(farthest + offset, as, voxel);
}

}  // namespace

double millimetres_per_unit(const std::string& unit) {
    if (unit == "mm") return 1;
    if (unit == "cm") return 10;
    if (unit == "m") return 1000;
    if (unit == "in") return 25.4;
    return 0;
}

void ShellSettings::validate() const {
    params.validate();
    fairing.validate();
    pieces.validate();
    if (!millimetres_per_unit(units)) throw ParameterError("unknown length unit '" + units + "': expected mm, cm, m or in");
    if (!(scale >= min_scale && scale <= max_scale))
        throw ParameterError(std::string("the scale must be ") + scale_range + format_text(", got %g", scale));
    if (mesh_ready && mesh_sink) throw ParameterError("the mesh goes to mesh_ready or to mesh_sink, not to both");
}

Shell make_shell(const PointSet& points, const ShellSettings& settings, const ProgressCallback& progress) {
    return make_shell(PointCloud(points), settings, progress);
}

namespace {

// Tells `progress` (where there is one) a message of `stage`; false back cancels.
void tell(const ProgressCallback& progress, const char* stage, std::string message, bool outcome = false) {
    if (!progress) return;
    Progress p;
    p.stage = stage;
    p.message = std::move(message);
    p.outcome = outcome;
    if (!progress(p)) throw Cancelled(std::string("cancelled in the ") + stage + " stage");
}

// A long loop of `stage` told as "<what> 47% <done_as>, about 13 s left", every few
// seconds at most.
detail::Told told_as(const ProgressCallback& progress, const char* stage, std::string what, std::string done_as) {
    if (!progress) return nullptr;
    return [=, pace = detail::ToldPace()](std::size_t done, std::size_t all) mutable {
        double left = 0;
        if (!pace.due(done, all, left)) return;
        tell(progress, stage,
             format_text("%s %.0f%% %s, about %.0f s left", what.c_str(), std::floor(100.0 * double(done) / double(all)),
                         done_as.c_str(), left));
    };
}

// What the depth guard did, the mesh stage's outcome ("" where it moved nothing).
std::string guard_outcome(const DepthGuardReport& guard, double depth) {
    if (!guard.moved_vertices) return "";
    const std::string except = guard.lone_points ? " but " + grouped(guard.lone_points) +
                                                       " with no other point within the offset (it is below the "
                                                       "sampling gap)"
                                                 : "";
    return grouped(guard.moved_vertices) + " vertices lifted along their normals, around " +
           grouped(guard.near_vertices) + " that came nearer to a point than the tube's inner wall (" +
           format_text("%.3g", depth) + " x offset), so that every point stays that deep" + except;
}

// make_shell's stages; `now` names the one running, for an allocation that fails.
Shell shell_stages(PointCloud points, const ShellSettings& given, const ProgressCallback& progress, const char*& now) {
    Stopwatch total, stage;
    Shell shell;
    const auto enter = [&progress, &now](const char* name) {
        now = name;
        Progress p;
        p.stage = name;
        if (progress && !progress(p)) throw Cancelled(std::string("cancelled before the ") + name + " stage");
    };
    given.validate();
    if (points.empty()) throw InputError("the point set is empty");
    shell.units = given.units;
    shell.to_millimetres = given.to_millimetres();
    const double to_mm = shell.to_millimetres;
    // Decided on the points as given, before any is dropped.
    const bool centre = given.origin == ShellOrigin::Centre ||
                        (given.origin == ShellOrigin::Auto &&
                         print_format_needs_centring(given.written_as, points, given.params, to_mm));
    shell.shift_by_default = centre && given.origin == ShellOrigin::Auto;
    // From here on every length is in millimetres: the points, the settings, the shell.
    ShellSettings settings = given;
    if (to_mm != 1) points.scale(to_mm);
    scale_lengths(settings.params, to_mm);
    // A tiled run need not put the whole field together where it is not asked for: its
    // tiles make the surface.
    settings.params.whole_field = settings.keep_field;
    // Such a surface is faired in slabs as it is welded, over the processes where there are several.
    if (!settings.keep_field) {
        settings.params.surface_fairing = settings.fairing;
        settings.params.surface_guard = true;
    }
    // And left in its slabs where it goes to a sink and no stage needs it whole.
    settings.params.surface_in_parts =
        settings.mesh_sink && !settings.keep_field && !settings.measure && settings.pieces.keeps_all();
    settings.pieces.min_volume *= to_mm * to_mm * to_mm;

    enter("outliers");
    {
        // Where the other processes filed the points too, they count part of the rules.
        detail::NeighbourCountsShared shared(settings.tiles_on.get(), points);
        if (settings.drop_outliers)
            shell.outliers = detail::drop_outliers_shared(
                points, settings.params, settings.outliers, {shared.short_of(), shared.roots_of(), shared.strays_of()},
                told_as(progress, "outliers", "lonely points", "tested against their neighbours' planes"));
    }
    if (centre) {
        shell.shift = round_centre(points);
        points.translate({-shell.shift[0], -shell.shift[1], -shell.shift[2]});
    }
    shell.points = points.size();
    shell.seconds.outliers = stage.lap();
    if (!shell.outliers.points.empty())  // what the stage did, before the long part
        tell(progress, "outliers",
             std::to_string(shell.outliers.points.size()) + " dropped, " + std::to_string(shell.points) + " kept", true);

    now = "reconstruction";
    shell.run = reconstruct(points, settings.params, progress, settings.tiles_on.get());
    Mesh surface = std::move(shell.run.surface);  // a tiled run's level set, moved on into the mesh
    detail::release_free_memory();
    shell.seconds.reconstruct = stage.lap();
    // The tiles' seams and weld are the mesh stage's work, done before it.
    shell.seconds.reconstruct -= shell.run.seconds.seams;
    shell.seconds.mesh = shell.run.seconds.seams;
    if (shell.run.tiles.worker) return shell;  // its tiles are the root's now
    const Result& run = shell.run;
    shell.warnings = run.warnings;

    enter("mesh");
    // Its parts said as each begins (12-22 s on the 12.5 M-point city block at 2048 cells).
    const detail::Begun begun = [&progress](const std::string& part) { tell(progress, "mesh", part); };
    // Over several processes, each searches its range of the points for the depth guard.
    TileScheduler* on = run.tiles.core_cells > 0 ? settings.tiles_on.get() : nullptr;
    {
        detail::GuardSearchShared guard_shared(on, points, shell.run.tiles);
        if (!run.surface_made) begun("extracting the zero level set");
        shell.mesh = detail::shell_mesh_of(run.surface_made ? std::move(surface) : detail::level_set_of(run), run, points,
                                           &shell.guard, settings.fairing, guard_shared.elsewhere(), begun);
        guard_shared.done();
    }
    const double depth = 1 - run.tube_inner / run.offset;
    if (const std::string lifted = guard_outcome(shell.guard, depth); !lifted.empty())
        tell(progress, "mesh", lifted, true);
    if (shell.guard.shallow_points)
        shell.warnings.push_back(std::to_string(shell.guard.shallow_points) + " points stay shallower than " +
                                 format_text("%.3g", depth) + " x offset after " +
                                 std::to_string(shell.guard.repair_rounds) + " repair rounds");
    shell.pieces = filter_pieces(shell.mesh, settings.pieces);
    if (shell.pieces.dropped && !shell.mesh.triangles.empty())
        tell(progress, "mesh",
             format_text("%zu solid piece%s dropped (%.4g mm^3 in all), %zu kept", shell.pieces.dropped,
                         shell.pieces.dropped == 1 ? "" : "s", shell.pieces.dropped_volume, shell.pieces.kept),
             true);
    // Where the slabs are the shell's only copy, this one's is its first part.
    const bool in_slabs = run.tiles.slabs_kept;
    const std::size_t triangles = in_slabs ? run.tiles.surface_triangles : shell.mesh.triangles.size();
    if (!triangles && shell.pieces.dropped)
        throw Error("every solid piece of the shell (" + std::to_string(shell.pieces.dropped) +
                    format_text(", %.4g in all) is smaller than the least volume kept, %g (--min-piece-volume): nothing "
                           "to write",
                           shell.pieces.dropped_volume, settings.pieces.min_volume));
    if (!triangles)
        throw Error("the reconstructed shell is empty (no triangles on the " + std::to_string(run.domain.nx) + " x " +
                    std::to_string(run.domain.ny) + " x " + std::to_string(run.domain.nz) + " grid, " +
                    format_text("offset %.6g, voxel %.6g); try a larger --offset or a finer --resolution", run.offset,
                           run.domain.h));
    detail::WrittenMoves moves;  // where the slabs are kept: this one's, the others' joined in the check
    if (!settings.written_as.empty()) {
        const std::string as = written_file(settings.written_as);
        if (in_slabs) moves = detail::written_moves(shell.mesh.vertices.data(), shell.mesh.vertices.size(), as);
        else require_written_precision(shell.mesh, as, run.domain.h);
        // As the file holds it, for the check too: writing it again changes nothing.
        shell.mesh = as_written(std::move(shell.mesh), as);
    }
    if (!settings.keep_field) shell.run.phi = Field();  // its memory goes to the check
    detail::release_free_memory();
    shell.seconds.mesh += stage.lap();

    enter("check");
    // The mesh is final: the caller may write it now.
    const auto hand_over = [&] {
        if (in_slabs || (!settings.mesh_ready && !settings.mesh_sink)) return;
        Stopwatch handing;
        if (settings.mesh_ready) settings.mesh_ready(shell.mesh);
        else hand_mesh(shell.mesh, *settings.mesh_sink);
        shell.seconds.mesh_ready = handing.lap();
    };
    std::optional<detail::SlabHandover> handover;  // where the slabs are kept
    // The walls and depths take a while (48 s for the 12.5 M-point city block at 2048
    // cells on one thread): how far they have come, every few seconds.
    const detail::Told told =
        told_as(progress, "check", "walls and depths", on && on->processes() > 1 ? "measured on this process" : "measured");
    // Over several processes, each measures the walls and points of its own tiles (the
    // mesh handed over once this one has measured its own part, the others finishing theirs).
    if (on && on->processes() > 1) {
        // (Where the slabs are kept, this one's own part is written meanwhile, the rest after.)
        const double writing = settings.mesh_ready || settings.mesh_sink
                                   ? detail::mesh_writing_seconds(written_file(settings.written_as),
                                                                  in_slabs ? shell.mesh.triangles.size() : triangles)
                                   : 0;
        // The shell is the slabs the others kept, but where a piece was dropped; its
        // vertices as they kept them (rounded as written) but where the depth guard ran here
        // on the whole surface.
        detail::SlabsForCheck slabs;
        if (run.surface_made && shell.pieces.dropped == 0)
            slabs.are = (detail::has_inner_wall(run) && !run.surface_guarded) || run.tiles.guard_rerun
                            ? detail::SlabsAre::Moved
                            : detail::SlabsAre::Kept;
        slabs.written_as = settings.written_as.empty() ? "" : written_file(settings.written_as);
        slabs.moves = moves;
        if (in_slabs) handover.emplace(*on, *settings.mesh_sink);
        slabs.handover = handover ? &*handover : nullptr;
        shell.quality = detail::check_sharing(shell.mesh, points, run, settings.measure, *on, shell.run.tiles, slabs,
                                              hand_over, writing, told);
    } else {
        hand_over();
        shell.quality = detail::measure_told(shell.mesh, points, run.offset, run.domain.h, settings.measure,
                                             told, detail::wall_rays_for(run.backend));
    }
    // The outlier rules' last count is this one when it was taken on these points (not
    // moved since) at this link (0.5-0.7 s for 1.5-25 M points, twice over).
    const DroppedOutliers& o = shell.outliers;
    shell.clusters = o.clusters && !centre && o.link == 2 * run.offset ? o.clusters
                                                                        : count_point_clusters(points, 2 * run.offset);
    for (std::string& w : shell_warnings(shell.quality, points.size(), shell.clusters, shell.pieces.dropped))
        shell.warnings.push_back(std::move(w));
    Bounds box = bounds(shell.mesh.vertices);
    if (handover) {  // over the slabs, handed on
        box = {handover->box()[0], handover->box()[1]};
        shell.seconds.mesh_ready = handover->seconds();
    }
    if (settings.mesh_sink) shell.mesh = Mesh();  // handed on
    shell.size = {box.extent(0), box.extent(1), box.extent(2)};
    const double across = box.longest();
    if (across < 2)
        shell.warnings.push_back(format_text("the shell is only %.3g mm across: if the points are not in millimetres, give "
                                        "--units (m, cm or in)",
                                        across));
    shell.seconds.check = stage.lap() - shell.seconds.mesh_ready;
    const detail::SpillFacts spilled = detail::spill_facts();
    MemoryFacts& memory = shell.run.memory;
    memory.spilled_arrays = spilled.arrays;
    memory.spilled_bytes = spilled.most_bytes;
    memory.spill_trims = spilled.trims;
    memory.spill_folder = spilled.arrays ? spilled.folder : "";
    memory.storage_read = spilled.arrays ? spilled.read_bytes : 0;
    memory.storage_written = spilled.arrays ? spilled.written_bytes : 0;
    shell.seconds.total = total.lap();
    return shell;
}

}  // namespace

Shell make_shell(PointCloud points, const ShellSettings& given, const ProgressCallback& progress) {
    const char* now = "settings";
    // The points are the run's now: they count against its budget, but for what of them
    // lies in a file. Under a budget, the points' arrays beyond it go to files in the
    // temporary folder (spilled_memory.hpp: the same answers, pages read back as needed).
    const std::size_t budget = given.params.max_memory.value_or(0);
    const std::size_t held = detail::heap_bytes(points);
    const detail::BudgetScope within(budget, held);
    const detail::SpillScope spill(budget, held, given.params.temp_dir);
    try {
        return shell_stages(std::move(points), given, progress, now);
    } catch (const std::bad_alloc&) {
        const std::string limit = detail::memory_limit_text();
        throw ResourceError(std::string("out of memory in the ") + now + " stage" +
                            (limit.empty() ? "" : " (" + limit + ")") + "; lower the resolution or raise the voxel size");
    }
}

}  // namespace snvr
