// Fitting the grid to the points: voxel size, padding, multigrid-friendly sizes,
// the default offset, and a memory estimate made before anything is allocated.
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "geometry/sampling_gap.hpp"
#include "geometry/sampling_holes.hpp"
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

// Lengths far beyond the points' box mean nothing (a shell around a speck) and their
// sums would overflow: each given one is held to kMaxLengthRatio times the box.
void check_lengths(const Parameters& params, const Box& box) {
    const double extent = box.longest();
    for (const auto& [length, name] : {std::pair{params.offset, "the offset (--offset)"},
                                       {params.thickness, "the thickness (--thickness)"},
                                       {params.voxel, "the voxel size (--voxel)"}, {params.eps, "eps (--eps)"},
                                       {params.xi, "xi (--xi)"}})
        if (length && extent > 0 && !(*length <= kMaxLengthRatio * extent))
            throw ParameterError(std::string(name) + " " + fmt(*length) + " is more than " + fmt(kMaxLengthRatio) +
                                 " times the points' extent " + fmt(extent) + ": give a length at most " +
                                 fmt(kMaxLengthRatio * extent));
}

// The voxel size: from the box and resolution, given, or fitted to the resolution.
double voxel_size(const PointCloud& points, const Parameters& params, const Box& box,
                  const std::optional<double>& offset, double gap) {
    if (params.box) return box.longest() / params.resolution;
    if (params.voxel) return *params.voxel;
    // N h = E + 2 (l + pad h): solve for h with the offset fixed (given or gap), or l = 2.5 h.
    const double E = box.longest();
    const double pad = padding_cells(params.xi ? 4.0 : params.xi_cells);
    const double free_cells = params.resolution - 2 * pad;
    if (free_cells < 8)
        throw ParameterError("resolution " + std::to_string(params.resolution) +
                             " leaves no room for the points inside the padding; use at least " +
                             std::to_string(int(2 * pad + 16)));
    const double fixed_l = offset ? *offset : gap;
    double h = (E + 2 * fixed_l) / free_cells;
    if (!offset && gap < params.offset_cells * h) h = E / (free_cells - 2 * params.offset_cells);
    if (!(h > 0))
        throw InputError("all " + std::to_string(points.size()) +
                         " points coincide: give --voxel or --offset to set the scale");
    return h;
}

// The offset (given, the sampling gap, or the default in voxels) and why.
void choose_offset(DomainPlan& plan, const Parameters& params, const std::optional<double>& offset, double h) {
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
}

// Where points are added (Parameters::add_points): at a random sampling's holes wider
// than the tube's inner side (everything that near a point stays inside the shell, so
// the hole stays closed; a hole between that and the offset can pinch open), and
// between the points where the sampling, not the grid, sets the offset.
void plan_added_points(DomainPlan& plan, const Parameters& params, const PointCloud& points,
                       const std::optional<double>& offset, double h) {
    if (!params.add_points) return;
    const double least = (1 - params.tube_inner) * plan.offset;
    // No sampling's hole that wide (a point cloud dense against the grid): nothing to ask.
    if (plan.gap > 0 && HoleRules::widest_gaps * plan.gap > least)
        plan.hole_share = share_bordering_holes(detail::tree_of(points), plan.gap);
    if (plan.hole_share >= HoleRules::random_share) plan.hole_least = least;
    if (!offset && plan.gap > params.offset_cells * h) plan.upsample_spacing = params.upsample_spacing * plan.offset;
}

// A width or a time step given in world or normalised units, in cells: held to the
// ranges of the same in cells.
void check_in_cells(double cells, double most, const char* name, const std::string& value, const char* unit,
                    double h) {
    if (!(cells > 0 && cells <= most))
        throw ParameterError(std::string(name) + " " + value + " is " + fmt(cells) + unit + " at voxel " + fmt(h) +
                             ": it must be above 0 and at most " + fmt(most) + unit);
}

// The grid: the box and its padding in cells, each axis a multiple of the coarsest
// level's cell, centred on the box.
void fit_grid(DomainPlan& plan, const Parameters& params, const Box& box, double h, double xi_cells) {
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
}

// The time step and the number of steps for the flow time.
void plan_steps(DomainPlan& plan, const Parameters& params) {
    const double h = plan.domain.h, L = plan.domain.length_scale();
    plan.dt = params.dt ? *params.dt : params.dt_cells * (h / L) * (h / L);
    const double dt_cells = plan.dt / ((h / L) * (h / L));
    if (params.dt) check_in_cells(dt_cells, ParameterLimits::max_dt_cells, "dt (--dt)", fmt(*params.dt), " h^2", h);
    if (params.steps) {
        plan.planned_steps = *params.steps;
        return;
    }
    const double steps = std::ceil(params.smoothing_cells / dt_cells - 1e-9);
    if (!(steps <= ParameterLimits::max_steps))
        throw ParameterError("the flow time (--smoothing) " + fmt(params.smoothing_cells) + " h^2 in steps of " +
                             fmt(dt_cells) + " h^2 (--dt-cells or --dt) would take " + fmt(steps) + " steps: at most " +
                             std::to_string(ParameterLimits::max_steps) + "; give a shorter flow time or a longer step");
    plan.planned_steps = int(steps);
}

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
    check_lengths(params, box);

    DomainPlan plan;
    plan.gap = sampling_gap(detail::tree_of(points));
    std::optional<double> offset = params.offset;
    if (params.thickness) offset = *params.thickness / 2;
    const double h = voxel_size(points, params, box, offset, plan.gap);
    choose_offset(plan, params, offset, h);
    plan_added_points(plan, params, points, offset, h);

    // xi in cells, whether given in cells or in world units (then it depends on h).
    const double xi_cells = params.xi ? *params.xi / eps_of_cells(1.0, h) : params.xi_cells;
    if (params.xi)
        check_in_cells(xi_cells, ParameterLimits::max_width_cells, "xi (--xi)", fmt(*params.xi), " cells", h);
    if (params.eps)
        check_in_cells(*params.eps / eps_of_cells(1.0, h), ParameterLimits::max_width_cells, "eps (--eps)",
                       fmt(*params.eps), " cells", h);
    plan.xi = eps_of_cells(xi_cells, h);
    plan.eps = params.eps ? *params.eps : eps_of_cells(params.eps_cells, h);
    fit_grid(plan, params, box, h, xi_cells);
    plan_steps(plan, params);
    if (params.keep_offset) {
        plan.tube_inner = params.tube_inner * plan.offset;
        plan.tube_outer = params.tube_outer * plan.offset;
    }

    // The solver's fields follow the band and are checked once it is known (the session).
    plan.estimated_bytes = estimate_plan_bytes(plan.domain);
    require_memory(plan.estimated_bytes, plan.domain);
    return plan;
}

}  // namespace snvr
