// The operations of a time step, written down once: each one's name, the fewest bytes
// it must move, and how it is called. The V-cycle runs them through run_operation (and
// counts its traffic from this table); the roofline benchmarks time every entry.
//
// Traffic model: an operation streams each field it touches once over the active
// bricks of its level (a stencil's neighbours come from cache); `streams` counts those
// fields per cell of the level, `coarse_streams` per cell of the next coarser level.
// A sweep is both colours fused, so phi, rhs and g are read once and phi written once.
#pragma once
#include "solver/backend.hpp"

namespace snvr {

enum class Operation { load_rhs, sweep, residual, restrict_residual, prolong_correct, coarse_solve, nonlinear };

struct OperationInfo {
    Operation op;
    const char* name;
    double streams;         // per cell of the level
    double coarse_streams;  // per cell of level + 1
};

inline constexpr OperationInfo kOperations[] = {
    {Operation::load_rhs, "copy (load_rhs)", 2, 0},          // phi in, rhs out
    {Operation::sweep, "red-black sweep", 4, 0},             // phi, rhs, g in, phi out
    {Operation::residual, "residual norm", 3, 0},            // phi, rhs, g in
    {Operation::restrict_residual, "restrict residual", 3, 3},  // phi, rhs, g in; rhs, phi out and g in below
    {Operation::prolong_correct, "prolong + correct", 3, 1},    // g, phi in, phi out; phi in below
    {Operation::coarse_solve, "coarse solve", 2, 0},         // rhs in, phi out; the inverse stays in cache
    {Operation::nonlinear, "nonlinear", 4, 0},               // phi, g, distance in, phi out
};

inline const OperationInfo& operation_info(Operation op) {
    for (const OperationInfo& info : kOperations)
        if (info.op == op) return info;
    return kOperations[0];  // unreachable: every Operation has its row
}

// What the calls need besides the level.
template <class Real>
struct OperationArgs {
    Real coefficient = 0;  // dt / h^2 of the level (dt_over_h2)
    Real omega = 1;        // over-relaxation of the sweep
    bool trilinear = true;
    Real rate = 0;         // the nonlinear step's k
    Tube<Real> tube;
};

// Runs one operation on `level`; the residual returns its sum of squares, the rest 0.
template <class Real>
double run_operation(Backend<Real>& b, Operation op, int level, const OperationArgs<Real>& a) {
    switch (op) {
        case Operation::load_rhs: b.load_rhs(); break;
        case Operation::sweep:
            b.smooth(level, 0, a.coefficient, a.omega);
            b.smooth(level, 1, a.coefficient, a.omega);
            break;
        case Operation::residual: return b.residual_sum_squares(level, a.coefficient);
        case Operation::restrict_residual: b.restrict_residual(level, a.coefficient); break;
        case Operation::prolong_correct: b.prolong_correct(level, a.trilinear); break;
        case Operation::coarse_solve: b.coarse_solve(level); break;
        case Operation::nonlinear: b.nonlinear(a.rate, a.tube); break;
    }
    return 0;
}

// Least bytes one run of `op` on `level` moves.
inline double operation_bytes(Operation op, const Hierarchy& h, int level, std::size_t real_size) {
    const OperationInfo& info = operation_info(op);
    double cells = info.streams * double(h.levels[std::size_t(level)].brick_cells);
    if (info.coarse_streams > 0 && level + 1 < int(h.levels.size()))
        cells += info.coarse_streams * double(h.levels[std::size_t(level) + 1].brick_cells);
    return cells * double(real_size);
}

}  // namespace snvr
