#include "solver/coarse_inverse.hpp"

#include <algorithm>
#include <cmath>

#include "snvr/error.hpp"

namespace snvr {

CoarseInverse coarse_inverse(const Level& lv, const std::vector<double>& g, double c) {
    CoarseInverse inv;
    std::vector<std::int64_t> index(g.size(), -1);  // cell -> row of S
    for (std::size_t n = 0; n < g.size(); ++n)
        if (g[n] > 0) {
            index[n] = std::int64_t(inv.cells.size());
            inv.cells.push_back(std::uint32_t(n));
        }
    const std::size_t n = inv.cells.size();
    if (n == 0 || n > kMaxCoarseInverse) return {};

    // S = G^-1 + c K on the coupled cells, row-major (symmetric).
    std::vector<double> s(n * n, 0.0);
    for (std::size_t r = 0; r < n; ++r) {
        const std::size_t cell = inv.cells[r];
        const int i = int(cell % std::size_t(lv.nx)), j = int(cell / std::size_t(lv.nx) % std::size_t(lv.ny)),
                  k = int(cell / (std::size_t(lv.nx) * std::size_t(lv.ny)));
        int count = 0;
        const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k}, {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
        for (const auto& q : nb) {
            if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= lv.nx || q[1] >= lv.ny || q[2] >= lv.nz) continue;
            ++count;  // every neighbour in the grid is in the stencil; those with g = 0 hold 0
            const std::int64_t col = index[std::size_t(q[0]) + std::size_t(lv.nx) * (std::size_t(q[1]) + std::size_t(lv.ny) * std::size_t(q[2]))];
            if (col >= 0) s[r * n + std::size_t(col)] = -c;
        }
        s[r * n + r] = 1 / g[cell] + c * count;
    }
    // Cholesky S = L L^T in place (lower triangle).
    for (std::size_t jj = 0; jj < n; ++jj) {
        double d = s[jj * n + jj];
        for (std::size_t t = 0; t < jj; ++t) d -= s[jj * n + t] * s[jj * n + t];
        if (!(d > 0)) throw Error("coarse solve: the coarsest operator is not positive definite");
        d = std::sqrt(d);
        s[jj * n + jj] = d;
        // Rows four at a time, each summed in its own order (the chains side by side).
        const std::ptrdiff_t quads = std::ptrdiff_t((n - jj - 1 + 3) / 4);
#pragma omp parallel for schedule(static) if (n - jj > 64)
        for (std::ptrdiff_t q = 0; q < quads; ++q) {
            const std::size_t r0 = jj + 1 + 4 * std::size_t(q), rows = std::min<std::size_t>(4, n - r0);
            double v[4] = {};
            const double* row[4];
            for (std::size_t k = 0; k < 4; ++k) {
                row[k] = &s[(r0 + std::min(k, rows - 1)) * n];
                v[k] = row[k][jj];
            }
            for (std::size_t t = 0; t < jj; ++t)
                for (std::size_t k = 0; k < 4; ++k) v[k] -= row[k][t] * s[jj * n + t];
            for (std::size_t k = 0; k < rows; ++k) s[(r0 + k) * n + jj] = v[k] / d;
        }
    }
    // L^T row by row, for the back substitutions: the same products in the same order, read
    // along a row instead of down a column.
    std::vector<double> lt(n * n, 0.0);
    for (std::size_t r = 0; r < n; ++r)
        for (std::size_t t = 0; t <= r; ++t) lt[t * n + r] = s[r * n + t];
    // Column col of S^-1 from L y = e_col, L^T x = y; M's column col is it over g_col.
    // Columns go kGroup at a time, each summed in its own order as alone (the bits are the
    // same), side by side: one column's sums are a chain of dependent subtractions, and a
    // tiled run's 45 inverses of up to 512 cells were 6% of it.
    constexpr std::size_t kGroup = 4;
    inv.matrix.assign(n * n, 0.0);
    const std::ptrdiff_t groups = std::ptrdiff_t((n + kGroup - 1) / kGroup);
#pragma omp parallel for schedule(dynamic, 2)
    for (std::ptrdiff_t gi = 0; gi < groups; ++gi) {
        const std::size_t c0 = std::size_t(gi) * kGroup, k_n = std::min(kGroup, n - c0), c1 = c0 + k_n;
        std::vector<double> x(n * kGroup, 0.0);  // x[r * kGroup + k]: column c0 + k
        for (std::size_t k = 0; k < k_n; ++k) x[(c0 + k) * kGroup + k] = 1;
        for (std::size_t r = c0; r < n; ++r) {
            double v[kGroup] = {};
            for (std::size_t k = 0; k < k_n; ++k) {
                const std::size_t col = c0 + k;
                if (r < col) continue;
                v[k] = x[r * kGroup + k];
                for (std::size_t t = col; t < std::min(r, c1); ++t) v[k] -= s[r * n + t] * x[t * kGroup + k];
            }
            for (std::size_t t = c1; t < r; ++t)
                for (std::size_t k = 0; k < kGroup; ++k) v[k] -= s[r * n + t] * x[t * kGroup + k];
            for (std::size_t k = 0; k < k_n; ++k)
                if (r >= c0 + k) x[r * kGroup + k] = v[k] / s[r * n + r];
        }
        for (std::size_t r = n; r-- > 0;) {
            double v[kGroup];
            for (std::size_t k = 0; k < kGroup; ++k) v[k] = x[r * kGroup + k];
            for (std::size_t t = r + 1; t < n; ++t)
                for (std::size_t k = 0; k < kGroup; ++k) v[k] -= lt[r * n + t] * x[t * kGroup + k];
            for (std::size_t k = 0; k < kGroup; ++k) x[r * kGroup + k] = v[k] / lt[r * n + r];
        }
        for (std::size_t k = 0; k < k_n; ++k) {
            const std::size_t col = c0 + k;
            const double scale = 1 / g[inv.cells[col]];
            for (std::size_t r = 0; r < n; ++r) inv.matrix[col * n + r] = x[r * kGroup + k] * scale;
        }
    }
    return inv;
}

}  // namespace snvr
