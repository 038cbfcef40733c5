#include "solver/multigrid.hpp"

#include "solver/operations.hpp"

#include <algorithm>
#include <cmath>

namespace snvr {

namespace {

template <class Real>
class VCycle {
public:
    VCycle(Backend<Real>& b, const Hierarchy& h, const MultigridSettings& s) : b_(b), h_(h), s_(s) {}

    double bytes_moved = 0;

    // Runs an operation (operations.hpp) on a level and counts its traffic.
    double run(Operation op, int level) {
        bytes_moved += operation_bytes(op, h_, level, sizeof(Real));
        OperationArgs<Real> a;
        a.coefficient = Real(dt_over_h2(s_.dt, h_.levels[std::size_t(level)]));
        a.omega = Real(s_.omega);
        a.trilinear = s_.trilinear;
        return run_operation(b_, op, level, a);
    }

    // RMS over the cells of the active bricks: the band's, not the box's (outside them
    // the residual is zero, and a box-wide mean would loosen tol as the box grows).
    double residual_norm() {
        return std::sqrt(run(Operation::residual, 0) / double(std::max<std::size_t>(h_.levels[0].brick_cells, 1)));
    }

    void cycle(int level) {
        if (level == s_.exact_level) {
            run(Operation::coarse_solve, level);
            return;
        }
        if (level == int(h_.levels.size()) - 1) {
            solve_coarsest(level);
            return;
        }
        sweeps(level, s_.pre_smooth);
        run(Operation::restrict_residual, level);
        cycle(level + 1);
        run(Operation::prolong_correct, level);
        sweeps(level, s_.post_smooth);
    }

private:
    void sweeps(int level, int times) {
        for (int n = 0; n < times; ++n) run(Operation::sweep, level);
    }

    // The coarsest grid is small (about 8 cells on its longest axis): sweep until the
    // residual has dropped a thousandfold. Its operator is an M-matrix, so this converges
    // for any dt; at the default dt a few sweeps suffice.
    void solve_coarsest(int level) {
        const double start = run(Operation::residual, level);
        if (start == 0) return;
        for (int n = 0; n < 500; n += 4) {
            sweeps(level, 4);
            if (run(Operation::residual, level) <= 1e-6 * start) return;
        }
    }

    Backend<Real>& b_;
    const Hierarchy& h_;
    const MultigridSettings& s_;
};

}  // namespace

template <class Real>
int prepare_coarse_levels(Backend<Real>& backend, const Hierarchy& hierarchy, const MultigridSettings& s) {
    const int coarsest = int(hierarchy.levels.size()) - 1;
    for (int l = 0; l < coarsest; ++l) backend.restrict_coefficient(l);
    if (!s.exact_coarse) return -1;
    // From the coarsest up, while the coupled cells stay few. Level 0 has rhs != 0
    // where g = 0, which the inverse leaves out: coarse levels only.
    std::vector<double> chosen_g;
    int chosen = -1;
    for (int l = coarsest; l >= 1; --l) {
        const Level& lv = hierarchy.levels[std::size_t(l)];
        std::vector<Real> g(lv.cells());
        backend.download(l, FieldKind::g, g.data());
        std::size_t coupled = 0;
        for (Real v : g) coupled += v > 0;
        if (coupled > kMaxCoarseInverse) break;
        chosen = l;
        chosen_g.assign(g.begin(), g.end());
    }
    if (chosen < 0) return -1;
    const Level& lv = hierarchy.levels[std::size_t(chosen)];
    backend.set_coarse_inverse(chosen, coarse_inverse(lv, chosen_g, dt_over_h2(s.dt, lv)));
    return chosen;
}

template <class Real>
LinearSolveStats solve_linear(Backend<Real>& backend, const Hierarchy& hierarchy, const MultigridSettings& s) {
    VCycle<Real> cycle(backend, hierarchy, s);
    cycle.run(Operation::load_rhs, 0);
    LinearSolveStats st;
    // The residual of the initial guess phi^n is dt g Lap phi^n.
    double r = cycle.residual_norm();
    st.initial_residual = r;
    while ((r >= s.tol && st.cycles < s.max_cycles) || st.cycles < s.min_cycles) {
        cycle.cycle(0);
        const double before = r;
        r = cycle.residual_norm();
        st.residuals.push_back(r);
        ++st.cycles;
        if (!std::isfinite(r)) break;
        // A cycle that gains less than a tenth has met the rounding floor of the field's
        // type (in float about dt / h^2 x 1e-7): more cycles would only spin.
        if (r > 0.9 * before && st.cycles >= s.min_cycles) break;
    }
    st.converged = r < s.tol;
    st.bytes_moved = cycle.bytes_moved;
    return st;
}

template int prepare_coarse_levels<double>(Backend<double>&, const Hierarchy&, const MultigridSettings&);
template int prepare_coarse_levels<float>(Backend<float>&, const Hierarchy&, const MultigridSettings&);
template LinearSolveStats solve_linear<double>(Backend<double>&, const Hierarchy&, const MultigridSettings&);
template LinearSolveStats solve_linear<float>(Backend<float>&, const Hierarchy&, const MultigridSettings&);

}  // namespace snvr
