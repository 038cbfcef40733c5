#include "solver/multigrid.hpp"

#include <cmath>

namespace snvr {

namespace {

// Memory traffic model: each operation streams its fields once over the active bricks
// (a stencil's neighbours come from cache). Streams counted per cell of the level:
// half sweep reads phi, rhs, g and writes phi; the residual reads three fields; the
// restriction reads three fine fields and writes two coarse ones (and reads coarse g);
// prolongation reads g and phi and writes phi, plus the coarse phi.
constexpr double kSweepStreams = 4, kResidualStreams = 3, kRestrictFine = 3, kRestrictCoarse = 3,
                 kProlongFine = 3, kProlongCoarse = 1, kCopyStreams = 2;

template <class Real>
class VCycle {
public:
    VCycle(Backend<Real>& b, const Hierarchy& h, const MultigridSettings& s) : b_(b), h_(h), s_(s) {}

    double bytes_moved = 0;
    void count(int level, double streams) {
        bytes_moved += streams * double(h_.levels[std::size_t(level)].brick_cells) * sizeof(Real);
    }

    Real coefficient(int level) const { return Real(dt_over_h2(s_.dt, h_.levels[std::size_t(level)])); }

    double residual_norm() {
        const Level& fine = h_.levels[0];
        count(0, kResidualStreams);
        return std::sqrt(b_.residual_sum_squares(0, coefficient(0)) / double(fine.cells()));
    }

    void run(int level) {
        if (level == s_.exact_level) {
            b_.coarse_solve(level);
            count(level, kCopyStreams);  // rhs in, phi out; the matrix stays in cache
            return;
        }
        if (level == int(h_.levels.size()) - 1) {
            solve_coarsest(level);
            return;
        }
        sweeps(level, s_.pre_smooth);
        b_.restrict_residual(level, coefficient(level));
        count(level, kRestrictFine);
        count(level + 1, kRestrictCoarse);
        run(level + 1);
        b_.prolong_correct(level, s_.trilinear);
        count(level, kProlongFine);
        count(level + 1, kProlongCoarse);
        sweeps(level, s_.post_smooth);
    }

private:
    void sweeps(int level, int times) {
        for (int n = 0; n < times; ++n) {
            b_.smooth(level, 0, coefficient(level), Real(s_.omega));
            b_.smooth(level, 1, coefficient(level), Real(s_.omega));
            count(level, kSweepStreams);  // two half sweeps each touch half the cells
        }
    }

    // The coarsest grid is small (about 8 cells on its longest axis): sweep until the
    // residual has dropped a thousandfold. Its operator is an M-matrix, so this converges
    // for any dt; at the default dt a few sweeps suffice.
    void solve_coarsest(int level) {
        const Real c = coefficient(level);
        const double start = b_.residual_sum_squares(level, c);
        count(level, kResidualStreams);
        if (start == 0) return;
        for (int n = 0; n < 500; n += 4) {
            sweeps(level, 4);
            count(level, kResidualStreams);
            if (b_.residual_sum_squares(level, c) <= 1e-6 * start) return;
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
    backend.load_rhs();
    cycle.count(0, kCopyStreams);
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
    st.bytes_moved = cycle.bytes_moved;
    return st;
}

double nonlinear_bytes(const Hierarchy& hierarchy, std::size_t real_size) {
    return 4.0 * double(hierarchy.levels[0].brick_cells) * double(real_size);
}

template int prepare_coarse_levels<double>(Backend<double>&, const Hierarchy&, const MultigridSettings&);
template int prepare_coarse_levels<float>(Backend<float>&, const Hierarchy&, const MultigridSettings&);
template LinearSolveStats solve_linear<double>(Backend<double>&, const Hierarchy&, const MultigridSettings&);
template LinearSolveStats solve_linear<float>(Backend<float>&, const Hierarchy&, const MultigridSettings&);

}  // namespace snvr
