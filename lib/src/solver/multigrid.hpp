// The linear half of a time step, phi* - dt g Lap_h phi* = phi^n (eq. 8), solved by
// geometric multigrid V-cycles with red-black Gauss-Seidel smoothing (eq. 9). The
// schedule is written once here, on top of the backend operations.
#pragma once
#include <vector>

#include "solver/backend.hpp"
#include "solver/hierarchy.hpp"

namespace snvr {

// Filled by multigrid_settings (problem.hpp) from Parameters, where the defaults live.
struct MultigridSettings {
    double dt = 0;          // normalised
    double tol = 0;         // on sqrt(sum r^2 / N) over the finest level's active-brick cells
    int max_cycles = 0;
    int min_cycles = 0;     // cycles run whatever the residual (tiles that must match others)
    int pre_smooth = 0, post_smooth = 0;
    double omega = 1;       // over-relaxation of the smoother
    bool trilinear = false;
    bool exact_coarse = false;  // solve a small coarse level exactly (prepare_coarse_levels)
    int exact_level = -1;       // the level the backend holds the inverse of; -1: none
};

// The operator's coefficient on a level, dt / h_l^2 (both normalised).
inline double dt_over_h2(double dt, const Level& level) { return dt / (level.h * level.h); }

struct LinearSolveStats {
    int cycles = 0;
    bool converged = false;
    double initial_residual = 0;
    std::vector<double> residuals;  // after each cycle
    double bytes_moved = 0;         // least memory traffic of the operations run (operations.hpp)
};

// Coarse coefficients for every level (once per run: g never changes) and, when
// s.exact_coarse, the inverse of the finest coarse level with at most
// kMaxCoarseInverse coupled cells: V-cycles stop there and solve it exactly. The band
// thins out with depth (bunny at 256: 275k, 28k, 2040, 4, 0 coupled cells on levels
// 1-5), so the coarsest levels often hold nothing to solve. Returns that level, or -1.
template <class Real>
int prepare_coarse_levels(Backend<Real>& backend, const Hierarchy& hierarchy, const MultigridSettings& s);

// Solves with phi (level 0) as both the right-hand side and the initial guess.
template <class Real>
LinearSolveStats solve_linear(Backend<Real>& backend, const Hierarchy& hierarchy, const MultigridSettings& s);

}  // namespace snvr
