// A coarse level's exact solve. There A phi = rhs with A = I - c G Lap (mirror
// boundary); where g = 0 the row is the identity and, on coarse levels, rhs = 0 (the
// restriction writes 0 there), so phi = 0 and only the cells with g > 0 couple:
// phi_a = M rhs_a with M = A_aa^-1, dense and computed once per run (g and c are fixed).
// A_aa = G_a (G_a^-1 + c K_aa), K = -Lap, so M = S^-1 G_a^-1 with S = G_a^-1 + c K_aa
// symmetric positive definite: a Cholesky factorisation gives it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "solver/hierarchy.hpp"

namespace snvr {

struct CoarseInverse {
    std::vector<std::uint32_t> cells;  // x-fastest indices of the cells with g > 0
    std::vector<double> matrix;        // M, n x n, column-major: M(r, c) at c * n + r
    std::size_t size() const { return cells.size(); }
};

// At most this many coupled cells: building the inverse costs about n^3 (0.05 s at
// 512 on 2 cores), each solve n^2.
constexpr std::size_t kMaxCoarseInverse = 512;

// `g` is the level's coefficient as a dense x-fastest array; c = dt / h^2 on the level.
// Empty when no cell has g > 0 or more than kMaxCoarseInverse do.
CoarseInverse coarse_inverse(const Level& level, const std::vector<double>& g, double c);

}  // namespace snvr
