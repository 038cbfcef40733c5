// Fitting the grid to the points: voxel size, padding, multigrid-friendly sizes,
// the default offset, and a memory estimate made before anything is allocated.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "geometry/sampling_gap.hpp"
#include "snvr/point_cloud.hpp"
#include "geometry/vec3_math.hpp"
#include "snvr/error.hpp"
#include "snvr/reconstruct.hpp"
#include "solver/solver_memory.hpp"

namespace snvr {

namespace {

using Box = Bounds;

std::string fmt(double v);

std::string fmt(double v) {
    std::ostringstream s;
    s.precision(4);
    s << v;
    return s.str();
}

// Cells of padding beyond the offset: the tanh profile decays over 8 xi to within
// 3e-5 of -1, plus two cells so the field is -1 on the boundary for the mesher.
double padding_cells(double xi_cells) { return 8.0 * eps_of_cells(xi_cells, 1.0) + 2.0; }

// Multigrid depth: coarsest longest axis of at least 8 cells (so the coarse solve is
// cheap) and every axis a multiple of 2^(levels-1).
int choose_levels(int longest) {
    int levels = 1;
    while (longest / (1 << levels) >= 8 && levels < 12) ++levels;
    return levels;
}

int round_up(int n, int m) { return (n + m - 1) / m * m; }

// A length option at most this many times the points' longest extent.
constexpr double kMaxLengthRatio = 1000;

}  // namespace

DomainPlan plan_domain(const PointSet& points, const Parameters& params) {
    if (points.empty()) throw InputError("the point set is empty");
    return plan_domain(PointCloud(points), params);
}

DomainPlan plan_domain(const PointCloud& points, const Parameters& params) {
    params.validate();
    if (points.empty()) throw InputError("the point set is empty");
    const std::array<Vec3, 2> cloud_box = points.box();
    const Box box = params.box ? Box{(*params.box)[0], (*params.box)[1]} : Box{cloud_box[0], cloud_box[1]};

    // Lengths far beyond the points' box mean nothing (a shell around a speck) and their
    // sums would overflow: each given one is held to kMaxLengthRatio times the box.
    const double extent = box.longest();
    for (const auto& [length, name] : {std::pair{params.offset, "the offset (--offset)"},
                                       {params.thickness, "the thickness (--thickness)"},
                                       {params.voxel, "the voxel size (--voxel)"}, {params.eps, "eps (--eps)"},
                                       {params.xi, "xi (--xi)"}})
        if (length && extent > 0 && !(*length <= kMaxLengthRatio * extent))
            throw ParameterError(std::string(name) + " " + fmt(*length) + " is more than " + fmt(kMaxLengthRatio) +
                                 " times the points' extent " + fmt(extent) + ": give a length at most " +
                                 fmt(kMaxLengthRatio * extent));

    DomainPlan plan;
    plan.gap = sampling_gap(detail::tree_of(points));
    std::optional<double> offset = params.offset;
    if (params.thickness) offset = *params.thickness / 2;

    // xi in cells, whether given in cells or in world units (then it depends on h).
    auto xi_in_cells = [&](double h) { return params.xi ? *params.xi / eps_of_cells(1.0, h) : params.xi_cells; };

    double h = 0;
    if (params.box) {
        h = box.longest() / params.resolution;
    } else if (params.voxel) {
        h = *params.voxel;
    } else {
        // N h = E + 2 (l + pad h): solve for h with the offset fixed (given or gap), or l = 2.5 h.
        const double E = box.longest();
        const double pad = padding_cells(params.xi ? 4.0 : params.xi_cells);
        const double free_cells = params.resolution - 2 * pad;
        if (free_cells < 8)
            throw ParameterError("resolution " + std::to_string(params.resolution) +
                                 " leaves no room for the points inside the padding; use at least " +
                                 std::to_string(int(2 * pad + 16)));
        const double fixed_l = offset ? *offset : plan.gap;
        h = (E + 2 * fixed_l) / free_cells;
        if (!offset && plan.gap < params.offset_cells * h) h = E / (free_cells - 2 * params.offset_cells);
        if (!(h > 0))
            throw InputError("all " + std::to_string(points.size()) +
                             " points coincide: give --voxel or --offset to set the scale");
    }

    if (offset) {
        plan.offset = *offset;
        plan.offset_reason = "given";
    } else if (plan.gap > params.offset_cells * h) {
        plan.offset = plan.gap;
        plan.offset_reason = "sampling gap (99th percentile of nearest-neighbour distances, " + fmt(plan.gap / h) +
                             " voxels)";
    } else {
        plan.offset = params.offset_cells * h;
        plan.offset_reason = fmt(params.offset_cells) + " voxels (" +
                             (params.offset_cells == Parameters{}.offset_cells ? "paper default; " : "") + "sampling gap " +
                             fmt(plan.gap / h) + " voxels)";
    }
    if (plan.offset < h)
        throw ParameterError("offset " + fmt(plan.offset) + " is smaller than one voxel (" + fmt(h) +
                             "): the shell cannot be resolved; raise the offset or the resolution");

    // A width or a time step given in world or normalised units, in cells: held to the
    // ranges of the same in cells.
    const auto in_cells = [&](double cells, double most, const char* name, const std::string& value, const char* unit) {
        if (!(cells > 0 && cells <= most))
            throw ParameterError(std::string(name) + " " + value + " is " + fmt(cells) + unit + " at voxel " + fmt(h) +
                                 ": it must be above 0 and at most " + fmt(most) + unit);
    };
    const double xi_cells = xi_in_cells(h);
    if (params.xi) in_cells(xi_cells, ParameterLimits::max_width_cells, "xi (--xi)", fmt(*params.xi), " cells");
    if (params.eps)
        in_cells(*params.eps / eps_of_cells(1.0, h), ParameterLimits::max_width_cells, "eps (--eps)", fmt(*params.eps),
                 " cells");
    plan.xi = eps_of_cells(xi_cells, h);
    plan.eps = params.eps ? *params.eps : eps_of_cells(params.eps_cells, h);

    Domain& d = plan.domain;
    d.h = h;
    int n[3];
    const double pad_world = params.box ? 0.0 : plan.offset + padding_cells(xi_cells) * h;
    for (int a = 0; a < 3; ++a) {
        const double cells = (box.extent(a) + 2 * pad_world) / h;
        if (!(cells < 1e6))
            throw ParameterError("the points span " + fmt(box.extent(a)) + " along " + std::string(1, "xyz"[a]) +
                                 ", which at voxel " + fmt(h) + " (and offset " + fmt(plan.offset) +
                                 ") would take " + fmt(cells) + " cells; give a larger --voxel" +
                                 (2 * pad_world > box.extent(a) ? " or a smaller --offset"
                                                                : ", or remove the points that stray far"));
        n[a] = std::max(1, int(std::ceil(cells - 1e-9)));
    }
    d.levels = choose_levels(std::max({n[0], n[1], n[2]}));
    const int m = 1 << (d.levels - 1);
    for (int a = 0; a < 3; ++a) {
        n[a] = round_up(n[a], m);
        const double centre = 0.5 * (box.lo[a] + box.hi[a]);
        d.origin[a] = centre - 0.5 * n[a] * h;
    }
    d.nx = n[0];
    d.ny = n[1];
    d.nz = n[2];

    const double L = d.length_scale();
    plan.dt = params.dt ? *params.dt : params.dt_cells * (h / L) * (h / L);
    const double dt_cells = plan.dt / ((h / L) * (h / L));
    if (params.dt) in_cells(dt_cells, ParameterLimits::max_dt_cells, "dt (--dt)", fmt(*params.dt), " h^2");
    if (!params.steps) {
        const double steps = std::ceil(params.smoothing_cells / dt_cells - 1e-9);
        if (!(steps <= ParameterLimits::max_steps))
            throw ParameterError("the flow time (--smoothing) " + fmt(params.smoothing_cells) + " h^2 in steps of " +
                                 fmt(dt_cells) + " h^2 (--dt-cells or --dt) would take " + fmt(steps) +
                                 " steps: at most " + std::to_string(ParameterLimits::max_steps) +
                                 "; give a shorter flow time or a longer step");
        plan.planned_steps = int(steps);
    } else {
        plan.planned_steps = *params.steps;
    }
    if (params.keep_offset) {
        plan.tube_inner = params.tube_inner * plan.offset;
        plan.tube_outer = params.tube_outer * plan.offset;
    }

    // The solver's fields follow the band and are checked once it is known (the session).
    plan.estimated_bytes = estimate_plan_bytes(d);
    require_memory(plan.estimated_bytes, d);
    return plan;
}

}  // namespace snvr
