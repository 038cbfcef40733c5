#include "openmp/openmp_backend.hpp"

#include <omp.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace snvr {

namespace {

// Sum of the present 6 neighbours (mirror boundary: a missing one equals the cell,
// so it drops out of the Laplacian) and how many there are. Fixed order: -x +x -y +y -z +z.
// Bricks away from the grid boundary take the branch-free path (all six present).
template <class Real>
inline Real neighbour_sum(const Real* p, std::size_t n, int i, int j, int k, const Level& lv, int& count) {
    const std::size_t sy = std::size_t(lv.nx), sz = std::size_t(lv.nx) * std::size_t(lv.ny);
    if (i > 0 && j > 0 && k > 0 && i < lv.nx - 1 && j < lv.ny - 1 && k < lv.nz - 1) {
        count = 6;
        return ((((p[n - 1] + p[n + 1]) + p[n - sy]) + p[n + sy]) + p[n - sz]) + p[n + sz];
    }
    Real s = 0;
    count = 0;
    if (i > 0) { s += p[n - 1]; ++count; }
    if (i < lv.nx - 1) { s += p[n + 1]; ++count; }
    if (j > 0) { s += p[n - sy]; ++count; }
    if (j < lv.ny - 1) { s += p[n + sy]; ++count; }
    if (k > 0) { s += p[n - sz]; ++count; }
    if (k < lv.nz - 1) { s += p[n + sz]; ++count; }
    return s;
}

template <class Real>
struct LevelFields {
    std::vector<Real> phi, rhs, g;
};

template <class Real>
class OpenMPBackend final : public Backend<Real> {
public:
    std::string name() const override { return "openmp (" + std::to_string(openmp_threads()) + " threads)"; }

    void setup(const Hierarchy& hier) override {
        hier_ = hier;
        fields_.assign(hier.levels.size(), {});
        for (std::size_t l = 0; l < hier.levels.size(); ++l) {
            const std::size_t n = hier.levels[l].cells();
            fields_[l].phi.assign(n, Real(0));
            fields_[l].rhs.assign(n, Real(0));
            fields_[l].g.assign(n, Real(0));
        }
    }

    std::size_t bytes() const override {
        std::size_t b = 0;
        for (const auto& f : fields_) b += (f.phi.size() + f.rhs.size() + f.g.size()) * sizeof(Real);
        return b;
    }

    void init_phase(const Real* d, Real l, Real s, Real cut) override {
        Real* phi = fields_[0].phi.data();
        Real* g = fields_[0].g.data();
        const std::ptrdiff_t n = std::ptrdiff_t(hier_.levels[0].cells());
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t c = 0; c < n; ++c) {
            const Real diff = l - d[c];
            if (std::abs(diff) > cut) {
                phi[c] = diff > 0 ? Real(1) : Real(-1);
                g[c] = 0;
            } else {
                const Real p = std::tanh(diff * s);
                phi[c] = p;
                g[c] = Real(1) - p * p;
            }
        }
    }

    void restrict_coefficient(int level) override {
        const Level& fine = hier_.levels[std::size_t(level)];
        const Real* gf = fields_[std::size_t(level)].g.data();
        Real* gc = fields_[std::size_t(level) + 1].g.data();
        for_cells(level + 1, [&](std::size_t n, int i, int j, int k) {
            Real sum = 0;
            bool zero = false;
            for_children(fine, i, j, k, [&](std::size_t f) {
                if (gf[f] == Real(0)) zero = true;
                else sum += Real(1) / gf[f];
            });
            gc[n] = zero ? Real(0) : Real(8) / sum;
        });
    }

    void load_rhs() override {
        const Real* phi = fields_[0].phi.data();
        Real* rhs = fields_[0].rhs.data();
        for_rows(0, [&](std::size_t n, int len) { std::memcpy(rhs + n, phi + n, std::size_t(len) * sizeof(Real)); });
    }

    void smooth(int level, int color, Real c) override {
        const Level& lv = hier_.levels[std::size_t(level)];
        LevelFields<Real>& f = fields_[std::size_t(level)];
        Real* phi = f.phi.data();
        const Real* rhs = f.rhs.data();
        const Real* g = f.g.data();
        const std::size_t sy = std::size_t(lv.nx), sz = std::size_t(lv.nx) * std::size_t(lv.ny);
        each_brick(level, [&](const CellRange& r, std::size_t) {
            if (is_interior(lv, r)) {
                // Whole rows at once (vectorisable): compute every cell, keep this colour's.
                // Where g = 0 the formula gives rhs, which phi already equals.
                for (int k = r.k0; k < r.k1; ++k)
                    for (int j = r.j0; j < r.j1; ++j) {
                        const std::size_t n0 = index(lv, r.i0, j, k);
                        Real next[kBrick];
                        for (int q = 0; q < kBrick; ++q) {
                            const std::size_t n = n0 + std::size_t(q);
                            const Real a = g[n] * c;
                            const Real s = ((((phi[n - 1] + phi[n + 1]) + phi[n - sy]) + phi[n + sy]) + phi[n - sz]) + phi[n + sz];
                            next[q] = (rhs[n] + a * s) / (Real(1) + a * Real(6));
                        }
                        for (int q = (r.i0 + j + k + color) & 1; q < kBrick; q += 2) phi[n0 + std::size_t(q)] = next[q];
                    }
                return;
            }
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j) {
                    const int i0 = r.i0 + ((r.i0 + j + k + color) & 1);
                    for (int i = i0; i < r.i1; i += 2) {
                        const std::size_t n = index(lv, i, j, k);
                        if (g[n] == Real(0)) continue;  // decoupled: phi already equals rhs
                        const Real a = g[n] * c;
                        int cnt;
                        const Real s = neighbour_sum(phi, n, i, j, k, lv, cnt);
                        phi[n] = (rhs[n] + a * s) / (Real(1) + a * Real(cnt));
                    }
                }
        });
    }

    double residual_sum_squares(int level, Real c) override {
        const Level& lv = hier_.levels[std::size_t(level)];
        std::vector<double> partial(lv.bricks.size(), 0.0);
        each_brick(level, [&](const CellRange& r, std::size_t t) {
            double s = 0;
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j)
                    for (int i = r.i0; i < r.i1; ++i) {
                        const double res = double(residual(level, c, i, j, k));
                        s += res * res;
                    }
            partial[t] = s;
        });
        double total = 0;
        for (double p : partial) total += p;
        return total;
    }

    void restrict_residual(int level, Real c) override {
        const Level& fine = hier_.levels[std::size_t(level)];
        const Real* gf = fields_[std::size_t(level)].g.data();
        LevelFields<Real>& cf = fields_[std::size_t(level) + 1];
        for_cells(level + 1, [&](std::size_t n, int i, int j, int k) {
            cf.phi[n] = 0;
            const Real gc = cf.g[n];
            if (gc == Real(0)) {
                cf.rhs[n] = 0;
                return;
            }
            Real sum = 0;
            for (int dk = 0; dk < 2; ++dk)
                for (int dj = 0; dj < 2; ++dj)
                    for (int di = 0; di < 2; ++di) {
                        const int fi = 2 * i + di, fj = 2 * j + dj, fk = 2 * k + dk;
                        sum += residual(level, c, fi, fj, fk) / gf[index(fine, fi, fj, fk)];
                    }
            cf.rhs[n] = gc * (sum * Real(0.125));
        });
    }

    void prolong_correct(int level, bool trilinear) override {
        const Level& coarse = hier_.levels[std::size_t(level) + 1];
        const Real* pc = fields_[std::size_t(level) + 1].phi.data();
        Real* phi = fields_[std::size_t(level)].phi.data();
        const Real* g = fields_[std::size_t(level)].g.data();
        for_cells(level, [&](std::size_t n, int i, int j, int k) {
            if (g[n] == Real(0)) return;
            const int I = i >> 1, J = j >> 1, K = k >> 1;
            if (!trilinear) {
                phi[n] += pc[index(coarse, I, J, K)];
                return;
            }
            // Cell-centred trilinear: weights 3/4 on the parent, 1/4 on the next coarse
            // cell towards this child (the parent itself at the boundary, by mirroring).
            const int I2 = clamp_index(I + ((i & 1) ? 1 : -1), coarse.nx);
            const int J2 = clamp_index(J + ((j & 1) ? 1 : -1), coarse.ny);
            const int K2 = clamp_index(K + ((k & 1) ? 1 : -1), coarse.nz);
            const Real w0 = Real(0.75), w1 = Real(0.25);
            auto row = [&](int jj, int kk) { return w0 * pc[index(coarse, I, jj, kk)] + w1 * pc[index(coarse, I2, jj, kk)]; };
            auto plane = [&](int kk) { return w0 * row(J, kk) + w1 * row(J2, kk); };
            phi[n] += w0 * plane(K) + w1 * plane(K2);
        });
    }

    void nonlinear(Real k) override {
        Real* phi = fields_[0].phi.data();
        const Real* g = fields_[0].g.data();
        for_cells(0, [&](std::size_t n, int, int, int) {
            if (g[n] == Real(0)) return;  // e = 1: phi unchanged
            const Real e = std::exp(-k * g[n]);
            const Real p = phi[n];
            phi[n] = p / std::sqrt(e + p * p * (Real(1) - e));
        });
    }

    void download_phi(Real* out) override {
        std::memcpy(out, fields_[0].phi.data(), fields_[0].phi.size() * sizeof(Real));
    }

private:
    static std::size_t index(const Level& lv, int i, int j, int k) {
        return std::size_t(i) + std::size_t(lv.nx) * (std::size_t(j) + std::size_t(lv.ny) * std::size_t(k));
    }
    // A full brick whose cells all have six neighbours inside the grid.
    static bool is_interior(const Level& lv, const CellRange& r) {
        return r.i0 > 0 && r.j0 > 0 && r.k0 > 0 && r.i1 < lv.nx && r.j1 < lv.ny && r.k1 < lv.nz &&
               r.i1 - r.i0 == kBrick;
    }
    static int clamp_index(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

    template <class F>
    static void for_children(const Level& fine, int i, int j, int k, F&& f) {
        for (int dk = 0; dk < 2; ++dk)
            for (int dj = 0; dj < 2; ++dj)
                for (int di = 0; di < 2; ++di) f(index(fine, 2 * i + di, 2 * j + dj, 2 * k + dk));
    }

    Real residual(int level, Real c, int i, int j, int k) const {
        const Level& lv = hier_.levels[std::size_t(level)];
        const LevelFields<Real>& f = fields_[std::size_t(level)];
        const std::size_t n = index(lv, i, j, k);
        const Real a = f.g[n] * c;
        int cnt;
        const Real s = neighbour_sum(f.phi.data(), n, i, j, k, lv, cnt);
        return (f.rhs[n] - f.phi[n]) + a * (s - Real(cnt) * f.phi[n]);
    }

    // Runs f(range, position in the brick list) for every active brick of the level.
    // Tiny levels run on one thread: waking the team costs more than the work.
    template <class F>
    void each_brick(int level, F&& f) const {
        const std::vector<std::uint32_t>& bricks = hier_.levels[std::size_t(level)].bricks;
        const Level& lv = hier_.levels[std::size_t(level)];
        const std::ptrdiff_t nb = std::ptrdiff_t(bricks.size());
#pragma omp parallel for schedule(static) if (nb > 16)
        for (std::ptrdiff_t t = 0; t < nb; ++t) f(lv.range(bricks[std::size_t(t)]), std::size_t(t));
    }
    template <class F>
    void for_cells(int level, F&& f) const {
        const Level& lv = hier_.levels[std::size_t(level)];
        each_brick(level, [&](const CellRange& r, std::size_t) {
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j)
                    for (int i = r.i0; i < r.i1; ++i) f(index(lv, i, j, k), i, j, k);
        });
    }
    template <class F>
    void for_rows(int level, F&& f) const {
        const Level& lv = hier_.levels[std::size_t(level)];
        each_brick(level, [&](const CellRange& r, std::size_t) {
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j) f(index(lv, r.i0, j, k), r.i1 - r.i0);
        });
    }

    Hierarchy hier_;
    std::vector<LevelFields<Real>> fields_;
};

}  // namespace

int openmp_threads() { return omp_get_max_threads(); }

template <class Real>
std::unique_ptr<Backend<Real>> make_openmp_backend() {
    return std::make_unique<OpenMPBackend<Real>>();
}

template std::unique_ptr<Backend<double>> make_openmp_backend<double>();
template std::unique_ptr<Backend<float>> make_openmp_backend<float>();

}  // namespace snvr
