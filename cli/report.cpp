#include "report.hpp"
#include "snvr/error.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <iostream>

namespace cli {

std::string fmt(const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string out(n > 0 ? std::size_t(n) : 0, '\0');
    if (n > 0) std::vsnprintf(out.data(), out.size() + 1, format, again);
    va_end(again);
    return out;
}

std::string grouped(std::size_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

void warn(const std::string& message) { std::cerr << "snvr-cl: warning: " << snvr::printable(message) << std::endl; }

void print_progress(std::ostream& out, const snvr::Progress& p) {
    if (p.stage == "step" && p.stats) {
        const snvr::StepStats& s = *p.stats;
        out << fmt("step %d/%d: %d V-cycle%s, residual %.2g, %.2f s%s", p.step, p.steps, s.cycles,
                   s.cycles == 1 ? "" : "s", s.residual, s.seconds_linear + s.seconds_nonlinear,
                   s.converged ? "" : " (not converged)");
    } else if (p.stage == "step") {
        out << fmt("step %d/%d", p.step, p.steps);
    } else {
        out << p.stage << (p.message.empty() ? "..." : ": " + snvr::printable(p.message));
    }
    if (p.stage == "step" && !p.message.empty()) out << ": " << p.message;
    out << std::endl;  // flushed: progress must show while the run goes on
}

namespace {

double mib(std::size_t bytes) { return double(bytes) / (1024.0 * 1024.0); }
const char* yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

std::size_t peak_rss_bytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
#if defined(__APPLE__)
    return std::size_t(usage.ru_maxrss);  // bytes on macOS
#else
    return std::size_t(usage.ru_maxrss) * 1024;  // KiB on Linux and the BSDs
#endif
}

snvr::Vec3 mesh_size(const snvr::Mesh& mesh) {
    if (mesh.vertices.empty()) return {0, 0, 0};
    snvr::Vec3 lo = mesh.vertices[0], hi = lo;
    for (const snvr::Vec3& v : mesh.vertices)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], v[a]);
            hi[a] = std::max(hi[a], v[a]);
        }
    return {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
}

CycleTotals cycle_totals(const snvr::Result& result) {
    CycleTotals c;
    for (const snvr::StepStats& s : result.steps) {
        c.total += s.cycles;
        c.most_in_a_step = std::max(c.most_in_a_step, s.cycles);
        c.not_converged += s.converged ? 0 : 1;
    }
    return c;
}

void print_summary(std::ostream& out, const RunSummary& run) {
    const snvr::Result& r = run.result;
    const snvr::Domain& d = r.domain;
    const double cells = double(d.cells());
    const CycleTotals cycles = cycle_totals(r);
    const int total_cycles = cycles.total, max_cycles = cycles.most_in_a_step, unconverged = cycles.not_converged;
    const auto row = [&out](const char* key, const std::string& value) {  // values may hold the user's file names
        out << "  " << key << std::string(17 - std::min<std::size_t>(17, std::char_traits<char>::length(key)), ' ')
            << snvr::printable(value) << '\n';
    };
    out << "summary:\n";
    if (run.outlier_link > 0)
        row("outliers", fmt("%s dropped, %s used (sparse, lone points standing off the surface, or in clusters of under %zu points apart by over %.3g mm)%s",
                            grouped(run.outliers).c_str(), grouped(run.points).c_str(),
                            snvr::OutlierSettings{}.min_cluster, run.outlier_link,
                            run.outliers_file.empty() ? "" : (": written to " + run.outliers_file).c_str()));
    row("grid", fmt("%d x %d x %d (%s cells), voxel %.6g, %d multigrid levels", d.nx, d.ny, d.nz,
                    grouped(d.cells()).c_str(), d.h, d.levels));
    if (run.shift != snvr::Vec3{0, 0, 0})
        row("origin", fmt("shifted by (%.17g, %.17g, %.17g): add that back to place the shell%s", -run.shift[0],
                          -run.shift[1], -run.shift[2],
                          run.shift_by_default ? " (float32 in this format would move it so far from the origin; "
                                                 "--origin keep keeps the coordinates)"
                                               : ""));
    row("offset", fmt("%.6g (%.3g voxels), thickness %.6g; why: %s", r.offset, r.offset / d.h, 2 * r.offset,
                      r.offset_reason.empty() ? "not reported" : r.offset_reason.c_str()));
    row("sampling gap", fmt("%.6g", r.gap));
    // In the cells of --eps-cells/--xi-cells, whichever way they were given.
    const double per_cell = snvr::eps_of_cells(1, d.h);
    row("eps, xi", fmt("%.6g (%.3g cells), %.6g (%.3g cells)", r.eps, r.eps / per_cell, r.xi, r.xi / per_cell));
    const double L = d.length_scale(), dt_cells = r.dt * (L / d.h) * (L / d.h);
    row("flow", fmt("%zu steps of dt %.3g (%.3g h^2): time %.3g h^2; %s", r.steps.size(), r.dt, dt_cells,
                    dt_cells * double(r.steps.size()),
                    r.tube_inner > 0 ? fmt("surface kept between %.3g and %.3g voxels from the points", (r.offset - r.tube_inner) / d.h,
                                           (r.offset + r.tube_outer) / d.h).c_str()
                                     : "free flow"));
    row("backend", r.backend);
    row("active cells", fmt("%s (%.1f%% of the grid)", grouped(r.active_cells).c_str(),
                            cells > 0 ? 100.0 * double(r.active_cells) / cells : 0.0));
    row("memory", fmt("solver %.1f MiB, peak RSS %.1f MiB", mib(r.solver_bytes), mib(peak_rss_bytes())));
    row("V-cycles", fmt("%d in %zu steps, at most %d in a step%s", total_cycles, r.steps.size(), max_cycles,
                        unconverged ? fmt(", %d not converged", unconverged).c_str() : ""));
    const snvr::StageSeconds& s = r.seconds;
    row("seconds", fmt("read %.2f, outliers %.2f, domain %.2f, distance %.2f, init %.2f, steps %.2f,",
                       run.seconds.read, run.seconds.outliers, s.domain, s.distance, s.init, s.steps));
    row("", fmt("mesh %.2f, write %.2f, check %.2f; total %.2f", run.seconds.mesh, run.seconds.write,
                run.seconds.check, run.seconds.total));
    const snvr::MeshQuality& q = run.quality;
    const snvr::MeshReport& m = q.report;
    row("size", fmt("%.4g x %.4g x %.4g mm%s", run.size[0], run.size[1], run.size[2],
                    run.to_mm == 1 ? " (lengths as read: --units mm)"
                                   : fmt(" (lengths in %s times %.6g)", run.units.c_str(), run.to_mm).c_str()));
    row("mesh", fmt("%s triangles, %s vertices, %zu component%s", grouped(m.triangles).c_str(),
                    grouped(m.vertices).c_str(), m.components, m.components == 1 ? "" : "s"));
    row("", fmt("%zu solid piece%s (the other components bound cavities)%s", m.solids, m.solids == 1 ? "" : "s",
                run.pieces.dropped ? fmt("; %zu dropped, %.4g mm^3 in all", run.pieces.dropped,
                                         run.pieces.dropped_volume).c_str()
                                   : ""));
    row("", fmt("closed %s, manifold %s, oriented %s%s", yes_no(m.closed()), yes_no(m.manifold()),
                yes_no(m.oriented()),
                m.zero_area_triangles ? fmt(", %zu zero-area triangles", m.zero_area_triangles).c_str() : ""));
    row("points enclosed", fmt("%s of %s; the nearest to the surface %.3g x offset deep (1st percentile %.3g)",
                               grouped(q.points_inside).c_str(), grouped(q.points).c_str(), q.depth_min, q.depth_p01));
    row("walls", fmt("thinnest 1%% at %.3g voxels = %.3g x 2 offset (thinnest of all %.3g voxels)", q.wall_p01,
                     q.wall_p01_2l, q.wall_min));
    if (q.has_surface)
        row("surface", fmt("distance to the points - offset: RMS %.3g voxels, mean %+.3g; dihedral RMS %.3g deg, "
                           "normal noise %.3g deg; genus %ld",
                           q.offset_rms, q.offset_mean, q.dihedral_rms, q.normal_noise, q.genus));
    else
        row("surface", fmt("genus %ld (distance to the offset and smoothness: --measure)", q.genus));
    row("wrote", run.output + (run.volume.empty() ? "" : ", " + run.volume));
    out.flush();
}

}  // namespace cli
