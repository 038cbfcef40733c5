#include "solver/coarse_inverse.hpp"

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
#pragma omp parallel for schedule(static) if (n - jj > 64)
        for (std::size_t r = jj + 1; r < n; ++r) {
            double v = s[r * n + jj];
            for (std::size_t t = 0; t < jj; ++t) v -= s[r * n + t] * s[jj * n + t];
            s[r * n + jj] = v / d;
        }
    }
    // Column col of S^-1 from L y = e_col, L^T x = y; M's column col is it over g_col.
    inv.matrix.assign(n * n, 0.0);
#pragma omp parallel for schedule(dynamic, 8)
    for (std::size_t col = 0; col < n; ++col) {
        std::vector<double> x(n, 0.0);
        x[col] = 1;
        for (std::size_t r = col; r < n; ++r) {
            double v = x[r];
            for (std::size_t t = col; t < r; ++t) v -= s[r * n + t] * x[t];
            x[r] = v / s[r * n + r];
        }
        for (std::size_t r = n; r-- > 0;) {
            double v = x[r];
            for (std::size_t t = r + 1; t < n; ++t) v -= s[t * n + r] * x[t];
            x[r] = v / s[r * n + r];
        }
        const double scale = 1 / g[inv.cells[col]];
        for (std::size_t r = 0; r < n; ++r) inv.matrix[col * n + r] = x[r] * scale;
    }
    return inv;
}

}  // namespace snvr
