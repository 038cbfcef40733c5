#include "multigrid.hpp"

#include <cmath>

namespace snvr {

namespace {

template <class Real>
class VCycle {
public:
    VCycle(Backend<Real>& b, const Hierarchy& h, const MultigridSettings& s) : b_(b), h_(h), s_(s) {}

    Real coefficient(int level) const {
        const double hl = h_.levels[std::size_t(level)].h;
        return Real(s_.dt / (hl * hl));
    }

    double residual_norm() {
        const Level& fine = h_.levels[0];
        return std::sqrt(b_.residual_sum_squares(0, coefficient(0)) / double(fine.cells()));
    }

    void run(int level) {
        const int coarsest = int(h_.levels.size()) - 1;
        if (level == coarsest) {
            solve_coarsest(level);
            return;
        }
        sweeps(level, s_.pre_smooth);
        b_.restrict_residual(level, coefficient(level));
        run(level + 1);
        b_.prolong_correct(level, s_.trilinear);
        sweeps(level, s_.post_smooth);
    }

private:
    void sweeps(int level, int count) {
        for (int n = 0; n < count; ++n) {
            b_.smooth(level, 0, coefficient(level));
            b_.smooth(level, 1, coefficient(level));
        }
    }

    // The coarsest grid is small (about 8 cells on its longest axis): sweep until the
    // residual has dropped a thousandfold. Its operator is an M-matrix, so this converges
    // for any dt; at the default dt a few sweeps suffice.
    void solve_coarsest(int level) {
        const Real c = coefficient(level);
        const double start = b_.residual_sum_squares(level, c);
        if (start == 0) return;
        for (int n = 0; n < 500; n += 4) {
            sweeps(level, 4);
            if (b_.residual_sum_squares(level, c) <= 1e-6 * start) return;
        }
    }

    Backend<Real>& b_;
    const Hierarchy& h_;
    const MultigridSettings& s_;
};

}  // namespace

template <class Real>
void prepare_coarse_levels(Backend<Real>& backend, const Hierarchy& hierarchy) {
    for (int l = 0; l + 1 < int(hierarchy.levels.size()); ++l) backend.restrict_coefficient(l);
}

template <class Real>
LinearSolveStats solve_linear(Backend<Real>& backend, const Hierarchy& hierarchy, const MultigridSettings& s) {
    VCycle<Real> cycle(backend, hierarchy, s);
    backend.load_rhs();
    LinearSolveStats st;
    // The residual of the initial guess phi^n is dt g Lap phi^n.
    double r = cycle.residual_norm();
    st.initial_residual = r;
    while (r >= s.tol && st.cycles < s.max_cycles) {
        cycle.run(0);
        r = cycle.residual_norm();
        st.residuals.push_back(r);
        ++st.cycles;
        if (!std::isfinite(r)) break;
    }
    st.converged = r < s.tol;
    return st;
}

template void prepare_coarse_levels<double>(Backend<double>&, const Hierarchy&);
template void prepare_coarse_levels<float>(Backend<float>&, const Hierarchy&);
template LinearSolveStats solve_linear<double>(Backend<double>&, const Hierarchy&, const MultigridSettings&);
template LinearSolveStats solve_linear<float>(Backend<float>&, const Hierarchy&, const MultigridSettings&);

}  // namespace snvr
