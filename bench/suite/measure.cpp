#include "measure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "host_measures.hpp"
#include "prepared_solver.hpp"
#include "solver/operations.hpp"
#include "table2.hpp"

namespace snvr::bench {

namespace {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Spread {
    double median = 0, min = 0, max = 0;
};

Spread spread_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return {n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]), v.front(), v.back()};
}

const char* precision_name(Precision p) { return p == Precision::Double ? "double" : "float"; }

void describe(Record& r, const std::string& section, const std::string& name, const Parameters& p) {
    r.set("section", section).set("case", name).set("device", p.device).set("precision", precision_name(p.precision));
}

template <class Real>
std::vector<Record> roofline(const std::string& label, const PointSet& points, const Parameters& params, int repeat) {
    PreparedSolver<Real> solver(points, params);
    Backend<Real>& b = *solver.backend;
    OperationArgs<Real> args;
    args.coefficient = solver.coefficient;
    args.omega = Real(params.omega);
    args.trilinear = params.trilinear;
    args.rate = Real(1e-3);
    args.tube = solver.tube;
    std::vector<Record> out;
    double copy_gbs = 0;
    for (const OperationInfo& op : kOperations) {
        if (op.op == Operation::coarse_solve) continue;  // coarse levels only
        const Spread s = spread_of(solver.samples(repeat, [&] { run_operation(b, op.op, 0, args); }));
        const double gb = operation_bytes(op.op, solver.hierarchy, 0, sizeof(Real)) / 1e9, gbs = gb / s.median;
        if (copy_gbs == 0) copy_gbs = gbs;
        Record r;
        describe(r, "roofline", label, params);
        r.set("backend", b.name()).set("kernel", op.name).set("ms", s.median * 1e3).set("ms_min", s.min * 1e3).set("ms_max", s.max * 1e3);
        r.set("gb", gb).set("gbps", gbs).set("of_copy", gbs / copy_gbs);
        out.push_back(r);
    }
    // A whole run at the same size: its steps against the bytes they must move.
    const Result res = reconstruct(points, params);
    double bytes = 0;
    for (const StepStats& s : res.steps) bytes += s.bytes_moved;
    Record run;
    describe(run, "roofline", label, params);
    run.set("backend", b.name()).set("kernel", "whole run: time steps").set("steps_s", res.seconds.steps);
    run.set("gb", bytes / 1e9).set("floor_s", bytes / 1e9 / copy_gbs).set("of_floor", bytes / 1e9 / copy_gbs / res.seconds.steps);
    run.set("total_s", res.seconds.total);
    out.push_back(run);
    return out;
}

}  // namespace

Record measure_run(const RunCase& c, int repeat, bool warm_up) {
    const PointSet points = c.points();
    std::vector<double> distance, init, steps, mesh, total;
    Result res;
    Mesh m;
    for (int r = warm_up ? 0 : 1; r <= repeat; ++r) {  // r = 0: warm-up, not counted
        res = Result();  // free the last run first: peak memory is one run's
        m = Mesh();
        res = reconstruct(points, c.params);
        const double t0 = now_seconds();
        m = extract_isosurface(res.phi, res.domain, 0.0, Interpolation::PhaseField);
        const double mesh_s = now_seconds() - t0;
        if (r == 0) continue;
        distance.push_back(res.seconds.distance);
        init.push_back(res.seconds.init);
        steps.push_back(res.seconds.steps);
        mesh.push_back(mesh_s);
        total.push_back(res.seconds.total + mesh_s);
    }
    Record rec;
    describe(rec, c.section, c.name, c.params);
    const Domain& d = res.domain;
    rec.set("backend", res.backend).set("nx", d.nx).set("ny", d.ny).set("nz", d.nz);
    rec.set("grid", std::to_string(d.nx) + "x" + std::to_string(d.ny) + "x" + std::to_string(d.nz));
    rec.set("cells", double(d.cells())).set("band_cells", double(res.active_cells)).set("points", double(points.size()));
    rec.set("steps", int(res.steps.size())).set("repeat", repeat).set("warm_up", warm_up ? "yes" : "no");
    const Spread st = spread_of(total);
    rec.set("distance_s", spread_of(distance).median).set("init_s", spread_of(init).median).set("steps_s", spread_of(steps).median);
    rec.set("mesh_s", spread_of(mesh).median).set("total_s", st.median).set("total_min_s", st.min).set("total_max_s", st.max);
    rec.set("spread", st.median > 0 ? (st.max - st.min) / st.median : 0.0);
    int cycles = 0;
    double worst_residual = 0, bytes = 0;
    for (const StepStats& s : res.steps) {
        cycles += s.cycles;
        worst_residual = std::max(worst_residual, s.residual);
        bytes += s.bytes_moved;
    }
    bool converged = true;
    for (const StepStats& s : res.steps) converged = converged && s.converged;
    rec.set("vcycles", cycles).set("max_residual", worst_residual).set("converged", converged ? "yes" : "no");
    rec.set("peak_rss_mib", peak_rss_mib()).set("solver_mib", double(res.solver_bytes) / (1 << 20));
    rec.set("bytes_moved_gb", bytes / 1e9).set("steps_gbps", bytes / 1e9 / spread_of(steps).median);
    if (!c.table2_shape.empty())
        for (const table2::Shape& s : table2::shapes())
            if (s.name == c.table2_shape) {
                const table2::Errors e = table2::surface_errors(m, s, c.params.offset.value_or(0.05));
                rec.set("grown", e.grown).set("shrunk", e.shrunk);
                const bool paper = d.nx == 128 || d.nx == 256;
                rec.set("paper_grown", paper ? (d.nx == 128 ? s.paper_grown_128 : s.paper_grown_256) : std::nan(""));
                rec.set("paper_shrunk", paper ? (d.nx == 128 ? s.paper_shrunk_128 : s.paper_shrunk_256) : std::nan(""));
            }
    return rec;
}

std::vector<Record> measure_roofline(const std::string& label, const std::function<PointSet()>& points, Parameters params,
                                     int repeat, bool host_triad) {
    const PointSet pts = points();
    std::vector<Record> out = params.precision == Precision::Double ? roofline<double>(label, pts, params, repeat)
                                                                    : roofline<float>(label, pts, params, repeat);
    if (host_triad) {
        Record r;
        describe(r, "roofline", label, params);
        r.set("backend", "host").set("kernel", "OpenMP triad (STREAM-like)").set("gbps", triad_bandwidth() / 1e9);
        out.push_back(r);
    }
    return out;
}

std::vector<Record> list_device_records() {
    std::vector<Record> out;
    for (const DeviceInfo& d : list_devices())
        if (d.available) out.push_back(Record().set("device", d.id).set("name", d.name).set("fp64", d.fp64 ? "yes" : "no"));
    return out;
}

}  // namespace snvr::bench
