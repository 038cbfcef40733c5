// report_summary (report.hpp): the run's figures as the rows snvr-cl prints under
// "summary:", lengths in millimetres.
#include <algorithm>
#include <cstdio>
#include <string>

#include "geometry/sampling_holes.hpp"
#include "snvr/error.hpp"
#include "snvr/report.hpp"

namespace snvr {
namespace {

double mib(std::size_t bytes) { return double(bytes) / (1024.0 * 1024.0); }

// Where the slabs kept their points deep too: the points given them, and the check's outcome.
std::string slab_guard_text(const TileFacts& t) {
    if (!t.guard_slabs)
        return t.guard_slab_points ? ", the points kept deep by the first (" + grouped(t.guard_slab_points) +
                                         " points near the others' slabs, more than their vertices)"
                                   : "";
    return ", the points kept deep in each (" + grouped(t.guard_slab_points) + " points given the others; " +
           (t.guard_rerun ? grouped(t.guard_ghosts_differing) +
                                " of their ghosts differed from their owners', so the guard ran again on the whole surface)"
                          : "their ghosts the same as their owners')");
}
const char* yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

std::string report_summary(const RunReport& report) {
    const Shell& run = report.shell;
    const Result& r = run.run;
    const RunFiles& files = report.files;
    const Domain& d = r.domain;
    const double cells = double(d.cells());
    std::string out;
    const auto row = [&out](const char* key, const std::string& value) {  // values may hold the user's file names
        out += "  " + std::string(key) +
               std::string(17 - std::min<std::size_t>(17, std::char_traits<char>::length(key)), ' ') +
               printable(value) + '\n';
    };
    if (run.outliers.link > 0)
        row("outliers", format_text("%s dropped, %s used (sparse, lone points standing off the surface, in clusters of under %zu points apart by over %.3g mm, or in small clusters far from the rest)%s",
                            grouped(run.outliers.points.size()).c_str(), grouped(run.points).c_str(),
                            OutlierSettings{}.min_cluster, run.outliers.link,
                            files.outliers_file.empty() ? "" : (": written to " + files.outliers_file).c_str()));
    row("grid", format_text("%d x %d x %d (%s cells), voxel %.6g, %d multigrid levels", d.nx, d.ny, d.nz,
                    grouped(d.cells()).c_str(), d.h, d.levels));
    if (run.shift != Vec3{0, 0, 0})
        row("origin", format_text("shifted by (%.17g, %.17g, %.17g): add that back to place the shell%s", -run.shift[0],
                          -run.shift[1], -run.shift[2],
                          run.shift_by_default ? " (float32 in this format would move it so far from the origin; "
                                                 "--origin keep keeps the coordinates)"
                                               : ""));
    row("offset", format_text("%.6g (%.3g voxels), thickness %.6g; why: %s", r.offset, r.offset / d.h, 2 * r.offset,
                      r.offset_reason.empty() ? "not reported" : r.offset_reason.c_str()));
    row("sampling gap", format_text("%.6g", r.gap));
    if (r.hole_share >= HoleRules::random_share)
        row("sampling holes", format_text("%s points added at the centres of holes wider than %.3g voxels (%.2g x offset; %.1f%% of the "
                                          "points border holes wider than the gap: a random sampling; --points-as-given leaves them)%s",
                                          grouped(r.hole_fills).c_str(), r.hole_least / d.h, r.hole_least / r.offset, 100 * r.hole_share,
                                          r.holes_sought_elsewhere ? ("; the holes at " + grouped(r.holes_sought_elsewhere) +
                                                                      " of the points sought by the other processes").c_str()
                                                                   : ""));
    if (r.upsample_spacing > 0)
        row("upsampled", format_text("%s points added %.3g voxels (%.2g x offset) apart on the points' local surfaces: the "
                                     "sampling sets the offset, and its balls would show (--points-as-given leaves them)%s",
                                     grouped(r.upsampled).c_str(), r.upsample_spacing / d.h, r.upsample_spacing / r.offset,
                                     r.upsampled_elsewhere ? ("; " + grouped(r.upsampled_elsewhere) +
                                                              " made by the other processes").c_str()
                                                           : ""));
    // In the cells of --eps-cells/--xi-cells, whichever way they were given.
    const double per_cell = eps_of_cells(1, d.h);
    row("eps, xi", format_text("%.6g (%.3g cells), %.6g (%.3g cells)", r.eps, r.eps / per_cell, r.xi, r.xi / per_cell));
    const double L = d.length_scale(), dt_cells = r.dt * (L / d.h) * (L / d.h);
    row("flow", format_text("%zu steps of dt %.3g (%.3g h^2): time %.3g h^2; %s", r.steps.size(), r.dt, dt_cells,
                    dt_cells * double(r.steps.size()),
                    r.tube_inner > 0 ? format_text("surface kept between %.3g and %.3g voxels from the points", (r.offset - r.tube_inner) / d.h,
                                           (r.offset + r.tube_outer) / d.h).c_str()
                                     : "free flow"));
    row("backend", r.backend);
    const TileFacts& t = r.tiles;
    if (t.core_cells > 0)
        row("tiles", format_text("%zu of %d cells a side, halo %d cells (%s), %zu with points run (%.2g x their cores' "
                                 "cells)%s in %.3g s, %zu run again to take as many V-cycles as the others; the largest: %s "
                                 "points, %s band cells%s",
                                 t.tiles, t.core_cells, t.halo_cells, t.halo_derived ? "as far as the flow reaches" : "as given",
                                 t.run, t.cells_run,
                                 t.processes > 1 ? format_text(" on %d processes (the busiest %.2f x the mean; %s points "
                                                               "given to the others%s, %.3g MiB of tiles sent back%s%s%s%s)",
                                                               t.processes, t.busiest_over_mean,
                                                               grouped(t.points_sent).c_str(),
                                                               t.points_from_ranges
                                                                   ? (" and " + grouped(t.points_from_ranges) +
                                                                      " taken from their own ranges")
                                                                         .c_str()
                                                                   : "",
                                                               mib(t.bytes_received),
                                                               t.faces_received
                                                                   ? format_text(", of which their faces' bricks %.3g MiB, "
                                                                                 "%.3g MiB a face",
                                                                                 mib(t.face_bytes),
                                                                                 mib(t.face_bytes) / double(t.faces_received))
                                                                         .c_str()
                                                                   : "",
                                                               t.slab_bytes
                                                                   ? format_text("; the surface welded and faired in %d "
                                                                                 "slabs of planes, %d planes of ghosts "
                                                                                 "either side, %.3g MiB between them%s%s",
                                                                                 t.slabs, t.slab_ghost, mib(t.slab_bytes),
                                                                                 slab_guard_text(t).c_str(),
                                                                                 t.slabs_kept ? ", kept in them and "
                                                                                                "written from them in turn"
                                                                                              : "")
                                                                         .c_str()
                                                                   : "",
                                                               t.check_bytes
                                                                   ? format_text("; the check's walls of %s vertices and depths "
                                                                                 "of %s points measured by the others (%.3g MiB "
                                                                                 "sent them, %s points asked of every slab)%s",
                                                                                 grouped(t.check_walls).c_str(),
                                                                                 grouped(t.check_points).c_str(),
                                                                                 mib(t.check_bytes),
                                                                                 grouped(t.check_points_far).c_str(),
                                                                                 t.check_topology_slabs
                                                                                     ? ", its topology counted by "
                                                                                       "the slabs"
                                                                                     : "")
                                                                         .c_str()
                                                                   : "",
                                                               t.guard_bytes
                                                                   ? format_text("; the depth guard's search of %s points "
                                                                                 "by the others (%.3g MiB sent them)",
                                                                                 grouped(t.guard_points).c_str(),
                                                                                 mib(t.guard_bytes))
                                                                         .c_str()
                                                                   : "")
                                                       .c_str()
                                                 : "",
                                 t.seconds,
                                 t.reruns,
                                 grouped(t.most_points).c_str(), grouped(t.most_band_cells).c_str(),
                                 r.memory.tiled_by_budget
                                     ? (r.memory.budget_given ? "; tiled to fit the memory budget (--max-memory)"
                                                              : "; tiled to fit the memory available")
                                     : ""));
    row("active cells", format_text("%s (%.1f%% of the grid)%s", grouped(r.active_cells).c_str(),
                            cells > 0 ? 100.0 * double(r.active_cells) / cells : 0.0,
                            t.core_cells > 0 ? ", the tiles' halos counted" : ""));
    const MemoryFacts& budget = r.memory;
    row("memory", format_text("solver %.1f MiB%s, peak RSS %.1f MiB%s", mib(r.solver_bytes),
                              t.core_cells > 0 ? " (the largest tile's)" : "", mib(report.peak_rss_bytes),
                              report.huge_page_bytes ? format_text(" (at the end %.1f MiB in huge pages)",
                                                                   mib(report.huge_page_bytes)).c_str()
                                                     : ""));
    if (budget.budget)
        row("", format_text("%s %.1f MiB%s: estimated peak %.1f MiB, set by %s (held %.1f MiB, the solver %.1f MiB "
                            "whole%s, %s %.1f%s, the mesh and its check %.1f, the grid's tables %.1f%s)",
                            budget.budget_given ? "budget" : "room", mib(budget.budget),
                            budget.budget_given ? " (--max-memory)" : " (held and available)", mib(budget.estimated_peak),
                            budget.bound.c_str(), mib(budget.held), mib(budget.whole_solver),
                            budget.tile_solver ? format_text(", %.1f MiB the largest tile", mib(budget.tile_solver)).c_str() : "",
                            budget.surfaces ? "the field's bricks at the tiles' faces" : "the phase field", mib(budget.field),
                            budget.surfaces ? format_text(", the tiles' surfaces %.1f", mib(budget.surfaces)).c_str() : "",
                            mib(budget.mesh), mib(budget.grid),
                            budget.runtime ? format_text(", the OpenCL runtime %.0f", mib(budget.runtime)).c_str() : ""));
    if (budget.spilled_arrays)
        row("", format_text("the points beyond the budget in files: %.1f MiB at most (%zu arrays, in %s), their pages "
                            "given back %zu times; %.1f MiB read from storage, %.1f MiB written",
                            mib(budget.spilled_bytes), budget.spilled_arrays, budget.spill_folder.c_str(),
                            budget.spill_trims, mib(budget.storage_read), mib(budget.storage_written)));
    const CycleTotals& c = report.cycles;
    row("V-cycles", format_text("%d in %zu steps, at most %d in a step%s", c.total, r.steps.size(), c.most_in_a_step,
                        c.not_converged ? format_text(", %d not converged", c.not_converged).c_str() : ""));
    const StageSeconds& s = r.seconds;
    row("seconds", format_text("read %.2f, outliers %.2f, domain %.2f, distance %.2f, init %.2f, steps %.2f,",
                       files.read_seconds, run.seconds.outliers, s.domain, s.distance, s.init, s.steps));
    row("", format_text("mesh %.2f, write %.2f, check %.2f; total %.2f", run.seconds.mesh, files.write_seconds,
                run.seconds.check, report.total_seconds));
    // Each stage's cost by its unit of work, a row a unit ("mesh 321, check 483 ns a triangle").
    const std::vector<StageUnit> units = stage_units(report);
    const char* key = "per unit";
    for (std::size_t i = 0; i < units.size();) {
        std::string stages;
        std::size_t j = i;
        for (; j < units.size() && units[j].unit == units[i].unit; ++j)
            if (units[j].units > 0) stages += format_text("%s%s %.3g", stages.empty() ? "" : ", ", units[j].stage.c_str(), units[j].ns);
        if (!stages.empty()) {
            row(key, stages + " ns a " + units[i].unit);
            key = "";
        }
        i = j;
    }
    const MeshQuality& q = run.quality;
    const MeshReport& m = q.report;
    row("size", format_text("%.4g x %.4g x %.4g mm%s", run.size[0], run.size[1], run.size[2],
                    run.to_millimetres == 1 ? " (lengths as read: --units mm)"
                                            : format_text(" (lengths in %s times %.6g)", run.units.c_str(), run.to_millimetres).c_str()));
    row("mesh", format_text("%s triangles, %s vertices, %zu component%s", grouped(m.triangles).c_str(),
                    grouped(m.vertices).c_str(), m.components, m.components == 1 ? "" : "s"));
    row("", format_text("%zu solid piece%s (the other components bound cavities)%s", m.solids, m.solids == 1 ? "" : "s",
                run.pieces.dropped ? format_text("; %zu dropped, %.4g mm^3 in all", run.pieces.dropped,
                                         run.pieces.dropped_volume).c_str()
                                   : ""));
    row("", format_text("closed %s, manifold %s, oriented %s%s", yes_no(m.closed()), yes_no(m.manifold()),
                yes_no(m.oriented()),
                m.zero_area_triangles ? format_text(", %zu zero-area triangles", m.zero_area_triangles).c_str() : ""));
    row("points enclosed", format_text("%s of %s; the nearest to the surface %.3g x offset deep (1st percentile %.3g)",
                               grouped(q.points_inside).c_str(), grouped(q.points).c_str(), q.depth_min, q.depth_p01));
    row("walls", format_text("thinnest 1%% at %.3g voxels = %.3g x 2 offset (thinnest of all %.3g voxels)%s", q.wall_p01,
                     q.wall_p01_2l, q.wall_min, q.walls_on == "host" ? "" : ("; rays cast on " + q.walls_on).c_str()));
    if (q.has_surface)
        row("surface", format_text("distance to the points - offset: RMS %.3g voxels, mean %+.3g; dihedral RMS %.3g deg, "
                           "normal noise %.3g deg; genus %ld",
                           q.offset_rms, q.offset_mean, q.dihedral_rms, q.normal_noise, q.genus));
    else
        row("surface", format_text("genus %ld (distance to the offset and smoothness: --measure)", q.genus));
    std::string wrote;
    for (const RunFiles::Output& o : files.outputs) wrote += (wrote.empty() ? "" : ", ") + o.path;
    if (!wrote.empty()) row("wrote", wrote);
    return out;
}

}  // namespace snvr
