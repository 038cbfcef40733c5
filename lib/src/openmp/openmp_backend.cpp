#include "openmp/openmp_backend.hpp"
#include "openmp/brick_grid.hpp"

#include <omp.h>

#include <cmath>
#include <cstring>
#include <type_traits>
#include <vector>

namespace snvr {

namespace {

template <class Real>
struct LevelFields {
    std::vector<Real> phi, rhs, g;  // brick-major (brick_grid.hpp)
};

// The six neighbours of the 8 cells of one brick row, in the fixed order -x +x -y +y
// -z +z, with 0 for a neighbour outside the grid, and how many are present. Adding the
// zeros leaves the sum bit-identical to skipping them (the mirror boundary: a missing
// neighbour equals the cell, so it drops out of the Laplacian).
template <class Real>
struct RowStencil {
    Real nb[6][kBrick];
    Real count[kBrick];
    int cells;  // valid cells in the row (fewer in a partial brick)

    Real sum(int q) const { return ((((nb[0][q] + nb[1][q]) + nb[2][q]) + nb[3][q]) + nb[4][q]) + nb[5][q]; }
};

template <class Real>
class OpenMPBackend final : public Backend<Real> {
public:
    std::string name() const override { return "openmp (" + std::to_string(openmp_threads()) + " threads)"; }

    void setup(const Hierarchy& hier) override {
        hier_ = hier;
        grids_.clear();
        fields_.assign(hier.levels.size(), {});
        for (std::size_t l = 0; l < hier.levels.size(); ++l) {
            grids_.emplace_back(hier.levels[l]);
            const std::size_t n = grids_[l].storage();
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
        const Level& lv = hier_.levels[0];
        const BrickGrid& bg = grids_[0];
        const std::ptrdiff_t nb = std::ptrdiff_t(lv.brick_count());
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t b = 0; b < nb; ++b) {
            const CellRange r = lv.range(std::uint32_t(b));
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j)
                    for (int i = r.i0; i < r.i1; ++i) {
                        const std::size_t c = bg.at(i, j, k);
                        const Real diff = l - d[std::size_t(i) + std::size_t(lv.nx) * (std::size_t(j) + std::size_t(lv.ny) * std::size_t(k))];
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
    }

    void restrict_coefficient(int level) override {
        const Real* gf = fields_[std::size_t(level)].g.data();
        const BrickGrid& fine = grids_[std::size_t(level)];
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
        const BrickGrid& bg = grids_[0];
        each_brick(0, [&](std::uint32_t b, std::size_t) {
            std::memcpy(rhs + bg.base(b), phi + bg.base(b), kBrickCells * sizeof(Real));
        });
    }

    void smooth(int level, int color, Real c) override {
        LevelFields<Real>& f = fields_[std::size_t(level)];
        Real* phi = f.phi.data();
        const Real* rhs = f.rhs.data();
        const Real* g = f.g.data();
        for_rows(level, phi, [&](std::size_t row, int j, int k, int i0, const RowStencil<Real>& st) {
            // Every cell of the row is computed (vectorisable), this colour's are kept.
            // Where g = 0 the formula gives rhs, which phi already equals.
            Real next[kBrick];
            for (int q = 0; q < kBrick; ++q) {
                const Real a = g[row + std::size_t(q)] * c;
                next[q] = (rhs[row + std::size_t(q)] + a * st.sum(q)) / (Real(1) + a * st.count[q]);
            }
            for (int q = (i0 + j + k + color) & 1; q < st.cells; q += 2) phi[row + std::size_t(q)] = next[q];
        });
    }

    double residual_sum_squares(int level, Real c) override {
        const Level& lv = hier_.levels[std::size_t(level)];
        std::vector<double> partial(lv.bricks.size(), 0.0);
        const LevelFields<Real>& f = fields_[std::size_t(level)];
        for_rows(level, f.phi.data(), [&](std::size_t row, int, int, int, const RowStencil<Real>& st, std::size_t t) {
            Real r[kBrick];
            residual_row(f, c, row, st, r);
            double s = 0;
            for (int q = 0; q < st.cells; ++q) s += double(r[q]) * double(r[q]);
            partial[t] += s;
        });
        double total = 0;
        for (double p : partial) total += p;
        return total;
    }

    // Each fine brick's children belong to a 4x4x4 block of one coarse brick, so fine
    // bricks write disjoint coarse cells. Coarse cells whose children lie in inactive
    // bricks have g_c = 0: their rhs and phi are zero from setup and stay zero.
    void restrict_residual(int level, Real c) override {
        const Level& fl = hier_.levels[std::size_t(level)];
        const LevelFields<Real>& ff = fields_[std::size_t(level)];
        const BrickGrid& fine = grids_[std::size_t(level)];
        const BrickGrid& coarse = grids_[std::size_t(level) + 1];
        LevelFields<Real>& cf = fields_[std::size_t(level) + 1];
        each_brick(level, [&](std::uint32_t b, std::size_t) {
            const CellRange r = fl.range(b);
            Real res[kBrickCells];
            RowStencil<Real> st;
            st.cells = r.i1 - r.i0;
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j) {
                    const std::size_t row = fine.at(r.i0, j, k);
                    gather(fine, ff.phi.data(), r, j, k, row, st);
                    residual_row(ff, c, row, st, res + BrickGrid::local(0, j - r.j0, k - r.k0));
                }
            const std::size_t base = fine.base(b);
            for (int k = r.k0 / 2; k < r.k1 / 2; ++k)
                for (int j = r.j0 / 2; j < r.j1 / 2; ++j)
                    for (int i = r.i0 / 2; i < r.i1 / 2; ++i) {
                        const std::size_t n = coarse.at(i, j, k);
                        cf.phi[n] = 0;
                        const Real gc = cf.g[n];
                        if (gc == Real(0)) {
                            cf.rhs[n] = 0;
                            continue;
                        }
                        Real sum = 0;
                        for (int dk = 0; dk < 2; ++dk)
                            for (int dj = 0; dj < 2; ++dj)
                                for (int di = 0; di < 2; ++di) {
                                    const int loc = BrickGrid::local(2 * i + di - r.i0, 2 * j + dj - r.j0, 2 * k + dk - r.k0);
                                    sum += res[loc] / ff.g[base + std::size_t(loc)];
                                }
                        cf.rhs[n] = gc * (sum * Real(0.125));
                    }
        });
    }

    void prolong_correct(int level, bool trilinear) override {
        const Level& fl = hier_.levels[std::size_t(level)];
        const Level& coarse = hier_.levels[std::size_t(level) + 1];
        const BrickGrid& fine = grids_[std::size_t(level)];
        const BrickGrid& cg = grids_[std::size_t(level) + 1];
        const Real* pc = fields_[std::size_t(level) + 1].phi.data();
        Real* phi = fields_[std::size_t(level)].phi.data();
        const Real* g = fields_[std::size_t(level)].g.data();
        constexpr int W = kBrick / 2 + 2;  // the brick's coarse cells and a one-cell halo
        each_brick(level, [&](std::uint32_t b, std::size_t) {
            const CellRange r = fl.range(b);
            const int I0 = r.i0 / 2 - 1, J0 = r.j0 / 2 - 1, K0 = r.k0 / 2 - 1;
            // Coarse values with the halo clamped: mirroring at the grid boundary.
            Real cv[W][W][W];
            for (int kk = 0; kk < W; ++kk)
                for (int jj = 0; jj < W; ++jj)
                    for (int ii = 0; ii < W; ++ii)
                        cv[kk][jj][ii] = pc[cg.at(clamp_index(I0 + ii, coarse.nx), clamp_index(J0 + jj, coarse.ny),
                                                  clamp_index(K0 + kk, coarse.nz))];
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j)
                    for (int i = r.i0; i < r.i1; ++i) {
                        const std::size_t n = fine.at(i, j, k);
                        if (g[n] == Real(0)) continue;
                        const int I = (i >> 1) - I0, J = (j >> 1) - J0, K = (k >> 1) - K0;
                        if (!trilinear) {
                            phi[n] += cv[K][J][I];
                            continue;
                        }
                        // Cell-centred trilinear: 3/4 on the parent, 1/4 on the next coarse
                        // cell towards this child.
                        const int I2 = I + ((i & 1) ? 1 : -1), J2 = J + ((j & 1) ? 1 : -1), K2 = K + ((k & 1) ? 1 : -1);
                        const Real w0 = Real(0.75), w1 = Real(0.25);
                        auto row = [&](int jj, int kk) { return w0 * cv[kk][jj][I] + w1 * cv[kk][jj][I2]; };
                        auto plane = [&](int kk) { return w0 * row(J, kk) + w1 * row(J2, kk); };
                        phi[n] += w0 * plane(K) + w1 * plane(K2);
                    }
        });
    }

    void nonlinear(Real k) override {
        Real* phi = fields_[0].phi.data();
        const Real* g = fields_[0].g.data();
        const BrickGrid& bg = grids_[0];
        each_brick(0, [&](std::uint32_t b, std::size_t) {
            for (std::size_t n = bg.base(b); n < bg.base(b) + kBrickCells; ++n) {
                if (g[n] == Real(0)) continue;  // e = 1: phi unchanged
                const Real e = std::exp(-k * g[n]);
                const Real p = phi[n];
                phi[n] = p / std::sqrt(e + p * p * (Real(1) - e));
            }
        });
    }

    void download_phi(Real* out) override {
        const Level& lv = hier_.levels[0];
        const BrickGrid& bg = grids_[0];
        const Real* phi = fields_[0].phi.data();
#pragma omp parallel for schedule(static)
        for (int k = 0; k < lv.nz; ++k)
            for (int j = 0; j < lv.ny; ++j)
                for (int i = 0; i < lv.nx; ++i)
                    out[std::size_t(i) + std::size_t(lv.nx) * (std::size_t(j) + std::size_t(lv.ny) * std::size_t(k))] =
                        phi[bg.at(i, j, k)];
    }

private:
    static int clamp_index(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

    template <class F>
    static void for_children(const BrickGrid& fine, int i, int j, int k, F&& f) {
        for (int dk = 0; dk < 2; ++dk)
            for (int dj = 0; dj < 2; ++dj)
                for (int di = 0; di < 2; ++di) f(fine.at(2 * i + di, 2 * j + dj, 2 * k + dk));
    }

    // r = rhs - A phi for the 8 cells of a row.
    static void residual_row(const LevelFields<Real>& f, Real c, std::size_t row, const RowStencil<Real>& st, Real* r) {
        for (int q = 0; q < kBrick; ++q) {
            const std::size_t n = row + std::size_t(q);
            const Real a = f.g[n] * c;
            r[q] = (f.rhs[n] - f.phi[n]) + a * (st.sum(q) - st.count[q] * f.phi[n]);
        }
    }

    // Runs f(brick id, position in the active list) for every active brick of the level.
    // Tiny levels run on one thread: waking the team costs more than the work.
    template <class F>
    void each_brick(int level, F&& f) const {
        const std::vector<std::uint32_t>& bricks = hier_.levels[std::size_t(level)].bricks;
        const std::ptrdiff_t nb = std::ptrdiff_t(bricks.size());
#pragma omp parallel for schedule(static) if (nb > 16)
        for (std::ptrdiff_t t = 0; t < nb; ++t) f(bricks[std::size_t(t)], std::size_t(t));
    }

    // f(storage index, i, j, k) for every cell of the active bricks.
    template <class F>
    void for_cells(int level, F&& f) const {
        const Level& lv = hier_.levels[std::size_t(level)];
        const BrickGrid& bg = grids_[std::size_t(level)];
        each_brick(level, [&](std::uint32_t b, std::size_t) {
            const CellRange r = lv.range(b);
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j)
                    for (int i = r.i0; i < r.i1; ++i) f(bg.at(i, j, k), i, j, k);
        });
    }

    // f(row start, j, k, i0, stencil[, position]) for every row of the active bricks,
    // with the row's neighbours gathered from `p`.
    template <class F>
    void for_rows(int level, const Real* p, F&& f) const {
        const Level& lv = hier_.levels[std::size_t(level)];
        const BrickGrid& bg = grids_[std::size_t(level)];
        each_brick(level, [&](std::uint32_t b, std::size_t t) {
            const CellRange r = lv.range(b);
            RowStencil<Real> st;
            st.cells = r.i1 - r.i0;
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j) {
                    const std::size_t row = bg.at(r.i0, j, k);
                    gather(bg, p, r, j, k, row, st);
                    if constexpr (std::is_invocable_v<F, std::size_t, int, int, int, const RowStencil<Real>&, std::size_t>)
                        f(row, j, k, r.i0, st, t);
                    else
                        f(row, j, k, r.i0, st);
                }
        });
    }

    // The row's neighbour values: inside the brick at fixed offsets, across a brick face
    // through the neighbouring brick, 0 (and not counted) outside the grid.
    static void gather(const BrickGrid& bg, const Real* p, const CellRange& r, int j, int k, std::size_t row,
                       RowStencil<Real>& st) {
        const int n = r.i1 - r.i0;
        const Real* self = p + row;
        for (int q = 0; q < kBrick; ++q) {
            const bool inside = q < n;
            st.nb[0][q] = q > 0 ? self[q - 1] : (r.i0 > 0 ? p[bg.at(r.i0 - 1, j, k)] : Real(0));
            st.nb[1][q] = q + 1 < n ? self[q + 1] : (inside && r.i0 + q + 1 < bg.nx ? p[bg.at(r.i0 + q + 1, j, k)] : Real(0));
            st.count[q] = Real(2) - Real(q == 0 && r.i0 == 0) - Real(inside && r.i0 + q + 1 >= bg.nx);
        }
        add_axis(bg, p, r, j, k, row, st, 1);
        add_axis(bg, p, r, j, k, row, st, 2);
    }

    // y (axis 1) or z (axis 2) neighbours of a row: whole rows, from this brick or the next.
    static void add_axis(const BrickGrid& bg, const Real* p, const CellRange& r, int j, int k, std::size_t row,
                         RowStencil<Real>& st, int axis) {
        const int c = axis == 1 ? j : k, size = axis == 1 ? bg.ny : bg.nz;
        const std::size_t stride = axis == 1 ? kBrick : kBrick * kBrick;
        const int lc = c % kBrick;
        for (int side = 0; side < 2; ++side) {
            const int nc = c + (side ? 1 : -1);
            Real* out = st.nb[2 * axis + side];
            if (nc < 0 || nc >= size) {
                for (int q = 0; q < kBrick; ++q) out[q] = 0;
                continue;
            }
            const bool same = side ? lc + 1 < kBrick : lc > 0;
            const Real* src = same ? p + (side ? row + stride : row - stride)
                                   : p + (axis == 1 ? bg.at(r.i0, nc, k) : bg.at(r.i0, j, nc));
            for (int q = 0; q < kBrick; ++q) {
                out[q] = src[q];
                st.count[q] += Real(1);
            }
        }
    }

    Hierarchy hier_;
    std::vector<BrickGrid> grids_;
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
