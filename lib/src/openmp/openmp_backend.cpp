#include "openmp/openmp_backend.hpp"
#include "fresh_vector.hpp"
#include "solver/brick_grid.hpp"
#include "solver/phase_math.hpp"
#include "solver/reduction.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstring>
#include <type_traits>
#include <vector>

namespace snvr {

namespace {

template <class Real>
struct LevelFields {
    std::vector<Real> phi;                 // brick-major (brick_grid.hpp)
    detail::FreshVector<Real> rhs, g;      // zeroed by zeroed_field
    std::vector<Real> distance;            // level 0 only: the normalised distance (for the tube)
};

// n zeros, each thread writing (and first touching) its own part: a serial assign faulted
// every page on one core.
template <class Real>
detail::FreshVector<Real> zeroed_field(std::size_t n) {
    detail::FreshVector<Real> f(n);
    constexpr std::size_t kPart = std::size_t(1) << 16;
    const std::ptrdiff_t parts = std::ptrdiff_t((n + kPart - 1) / kPart);
#pragma omp parallel for schedule(static) if (parts > 1)
    for (std::ptrdiff_t p = 0; p < parts; ++p) {
        const std::size_t first = std::size_t(p) * kPart;
        std::fill(f.data() + first, f.data() + std::min(n, first + kPart), Real(0));
    }
    return f;
}

// The neighbours of the 8 cells of one brick row: the row itself for -x/+x (and the
// cells just beyond its ends), whole rows for -y +y -z +z, taken from this brick or
// the next one; outside the grid a row of zeros and a lower count. Adding those zeros
// leaves the sum bit-identical to skipping them (the mirror boundary: a missing
// neighbour equals the cell, so it drops out of the Laplacian). Fixed summation
// order: -x +x -y +y -z +z, the same as the kernels.
template <class Real>
struct RowStencil {
    const Real* self;
    const Real *ym, *yp, *zm, *zp;
    Real xm_end, xp_end;  // -x neighbour of cell 0, +x neighbour of cell 7
    Real count[kBrick];
    int cells;            // valid cells in the row (fewer in a partial brick)

    Real sum(int q) const {
        const Real left = q > 0 ? self[q - 1] : xm_end;
        const Real right = q < kBrick - 1 ? self[q + 1] : xp_end;
        return ((((left + right) + ym[q]) + yp[q]) + zm[q]) + zp[q];
    }
};

template <class Real>
class OpenMPBackend final : public Backend<Real> {
public:
    std::string name() const override { return "openmp (" + std::to_string(openmp_threads()) + " threads)"; }

    void setup(const BrickLayout& layout) override {
        hier_ = layout.hierarchy;
        grids_ = layout.grids;
        fields_.assign(hier_.levels.size(), {});
        for (std::size_t l = 0; l < hier_.levels.size(); ++l) {
            const std::size_t n = grids_[l].storage();
            fields_[l].phi.assign(n, Real(0));
            fields_[l].rhs = zeroed_field<Real>(n);
            fields_[l].g = zeroed_field<Real>(n);
            std::fill_n(fields_[l].phi.begin() + kPlusSlot * kBrickCells, kBrickCells, Real(1));
            std::fill_n(fields_[l].phi.begin() + kMinusSlot * kBrickCells, kBrickCells, Real(-1));
        }
        // Level 0's distance arrives with init_phase.
    }

    std::size_t bytes() const override {
        std::size_t b = 0;
        for (const auto& f : fields_) b += (f.phi.size() + f.rhs.size() + f.g.size() + f.distance.size()) * sizeof(Real);
        return b;
    }

    void init_phase(std::vector<Real> distance, Real l, Real s, Real cut) override {
        fields_[0].distance = std::move(distance);
        fields_[0].distance.resize(grids_[0].storage(), Real(0));
        Real* phi = fields_[0].phi.data();
        Real* g = fields_[0].g.data();
        const Real* d = fields_[0].distance.data();
        for_cells(0, [&](std::size_t c, int, int, int) {
            const Real diff = l - d[c];
            if (std::abs(diff) > cut) {
                phi[c] = diff > 0 ? Real(1) : Real(-1);
                g[c] = 0;
            } else {
                const Real p = detail::tanh_of(diff * s);
                phi[c] = p;
                g[c] = Real(1) - p * p;
            }
        });
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

    void smooth(int level, int color, Real c, Real omega) override {
        LevelFields<Real>& f = fields_[std::size_t(level)];
        Real* phi = f.phi.data();
        const Real* rhs = f.rhs.data();
        const Real* g = f.g.data();
        for_rows(level, phi, [&](std::size_t row, int j, int k, int i0, const RowStencil<Real>& st) {
            // No test for g = 0: there the update gives rhs, which phi already equals,
            // and a branch on the band's ragged edge mispredicts more than it saves.
            for (int q = (i0 + j + k + color) & 1; q < st.cells; q += 2) {
                const std::size_t n = row + std::size_t(q);
                const Real a = g[n] * c;
                const Real gs = (rhs[n] + a * st.sum(q)) / (Real(1) + a * st.count[q]);
                phi[n] = omega == Real(1) ? gs : phi[n] + omega * (gs - phi[n]);
            }
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
        return chunked_sum(partial);
    }

    // Each fine brick's children belong to a 4x4x4 block of one coarse brick, so fine
    // bricks write disjoint coarse cells. Coarse cells whose children lie in inactive
    // bricks have g_c = 0: their rhs and phi are zero from setup and stay zero.
    void restrict_residual(int level, Real c) override {
        const LevelFields<Real>& ff = fields_[std::size_t(level)];
        const BrickGrid& fine = grids_[std::size_t(level)];
        const BrickGrid& coarse = grids_[std::size_t(level) + 1];
        LevelFields<Real>& cf = fields_[std::size_t(level) + 1];
        // Each thread's residuals of the brick it is on.
        std::vector<std::array<Real, kBrickCells>> scratch(static_cast<std::size_t>(omp_get_max_threads()));
        const auto rows = [&](std::size_t row, int j, int k, int, const RowStencil<Real>& st) {
            const std::size_t offset = std::size_t(BrickGrid::local(0, j % kBrick, k % kBrick));
            residual_row(ff, c, row, st, scratch[std::size_t(omp_get_thread_num())].data() + offset);
        };
        for_rows(level, ff.phi.data(), rows, [&](std::uint32_t b, const CellRange& r) {
            const Real* res = scratch[std::size_t(omp_get_thread_num())].data();
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
            const Real w0 = Real(0.75), w1 = Real(0.25);
            // Cell-centred trilinear: 3/4 on the parent, 1/4 on the next coarse cell towards
            // the child, separably: x first, then y, then z (the kernels' order).
            Real along_x[W][W][kBrick];  // [coarse k][coarse j][fine i]
            for (int kk = 0; kk < W; ++kk)
                for (int jj = 0; jj < W; ++jj)
                    for (int q = 0; q < r.i1 - r.i0; ++q) {
                        const int i = r.i0 + q, I = (i >> 1) - I0, I2 = I + ((i & 1) ? 1 : -1);
                        along_x[kk][jj][q] = trilinear ? w0 * cv[kk][jj][I] + w1 * cv[kk][jj][I2] : cv[kk][jj][I];
                    }
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j) {
                    const int J = (j >> 1) - J0, J2 = J + ((j & 1) ? 1 : -1);
                    const int K = (k >> 1) - K0, K2 = K + ((k & 1) ? 1 : -1);
                    const std::size_t row = fine.at(r.i0, j, k);
                    for (int q = 0; q < r.i1 - r.i0; ++q) {
                        const std::size_t n = row + std::size_t(q);
                        if (g[n] == Real(0)) continue;
                        if (!trilinear) {
                            phi[n] += along_x[K][J][q];
                            continue;
                        }
                        const Real plane_k = w0 * along_x[K][J][q] + w1 * along_x[K][J2][q];
                        const Real plane_k2 = w0 * along_x[K2][J][q] + w1 * along_x[K2][J2][q];
                        phi[n] += w0 * plane_k + w1 * plane_k2;
                    }
                }
        });
    }

    void set_coarse_inverse(int level, const CoarseInverse& inv) override {
        coarse_cells_ = storage_positions(grids_[std::size_t(level)], inv.cells);
        coarse_matrix_.assign(inv.matrix.begin(), inv.matrix.end());
        coarse_rhs_.resize(inv.size());
    }

    void coarse_solve(int level) override {
        LevelFields<Real>& f = fields_[std::size_t(level)];
        const std::ptrdiff_t n = std::ptrdiff_t(coarse_cells_.size());
        for (std::ptrdiff_t c = 0; c < n; ++c) coarse_rhs_[std::size_t(c)] = f.rhs[coarse_cells_[std::size_t(c)]];
#pragma omp parallel for schedule(static) if (n > 256)
        for (std::ptrdiff_t r = 0; r < n; ++r) {
            Real s = 0;
            for (std::ptrdiff_t c = 0; c < n; ++c) s += coarse_matrix_[std::size_t(c * n + r)] * coarse_rhs_[std::size_t(c)];
            f.phi[coarse_cells_[std::size_t(r)]] = s;
        }
    }

    void nonlinear(Real k, const Tube<Real>& tube) override {
        Real* phi = fields_[0].phi.data();
        const Real* g = fields_[0].g.data();
        const Real* d = fields_[0].distance.data();
        const BrickGrid& bg = grids_[0];
        each_brick(0, [&](std::uint32_t b, std::size_t) {
            // Every cell, then kept where g = 0 (e = 1: phi unchanged, and +-1 is inside
            // the tube): a loop without branches vectorises.
            for (std::size_t n = bg.base(b); n < bg.base(b) + kBrickCells; ++n) {
                const Real e = detail::exp_nonpositive(-k * g[n]);
                const Real p = phi[n];
                Real q = p / std::sqrt(e + p * p * (Real(1) - e));
                q = std::min(std::max(q, detail::tanh_of((tube.inner - d[n]) * tube.s)),
                             detail::tanh_of((tube.outer - d[n]) * tube.s));
                phi[n] = g[n] == Real(0) ? p : q;
            }
        });
    }

    void upload(int level, FieldKind field, const Real* dense) override {
        pack_active(grids_[std::size_t(level)], hier_.levels[std::size_t(level)], dense, storage(level, field));
    }

    void download(int level, FieldKind field, Real* dense) override {
        unpack(grids_[std::size_t(level)], storage(level, field), dense);
    }

    std::vector<Real> take_phase() override {
        std::vector<Real> phi = std::move(fields_[0].phi);
        fields_.clear();
        return phi;
    }

private:
    Real* storage(int level, FieldKind field) {
        LevelFields<Real>& f = fields_[std::size_t(level)];
        switch (field) {
            case FieldKind::phi: return f.phi.data();
            case FieldKind::rhs: return f.rhs.data();
            case FieldKind::g: return f.g.data();
            case FieldKind::distance: break;
        }
        return f.distance.data();
    }

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
    // with the row's neighbours taken from `p`; then done(brick, cell range), on the
    // same thread, once the brick's rows are through.
    struct Nothing {
        void operator()(std::uint32_t, const CellRange&) const {}
    };
    template <class F, class Done = Nothing>
    void for_rows(int level, const Real* p, F&& f, Done&& done = Done()) const {
        const Level& lv = hier_.levels[std::size_t(level)];
        const BrickGrid& bg = grids_[std::size_t(level)];
        static const Real zeros[kBrick] = {};
        each_brick(level, [&](std::uint32_t b, std::size_t t) {
            const CellRange r = lv.range(b);
            const int bi = r.i0 / kBrick, bj = r.j0 / kBrick, bk = r.k0 / kBrick;
            // Start of each neighbouring brick (-x +x -y +y -z +z), or none at the grid edge.
            const std::size_t none = std::size_t(-1);
            const std::uint32_t bx = std::uint32_t(bg.bx), bxy = bx * std::uint32_t(bg.by);
            const std::size_t here = bg.base(b);
            const std::size_t nb[6] = {bi > 0 ? bg.base(b - 1) : none,
                                       bi + 1 < bg.bx ? bg.base(b + 1) : none,
                                       bj > 0 ? bg.base(b - bx) : none,
                                       bj + 1 < bg.by ? bg.base(b + bx) : none,
                                       bk > 0 ? bg.base(b - bxy) : none,
                                       bk + 1 < bg.bz ? bg.base(b + bxy) : none};
            RowStencil<Real> st{};
            st.cells = r.i1 - r.i0;
            bool six = false;  // st.count holds all sixes
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j) {
                    const int lj = j - r.j0, lk = k - r.k0;
                    const std::size_t row = here + std::size_t(BrickGrid::local(0, lj, lk));
                    st.self = p + row;
                    // Rows across a brick face come from the neighbour's opposite face.
                    auto across = [&](int side, int cj, int ck) {
                        return nb[side] == none ? zeros : p + nb[side] + std::size_t(BrickGrid::local(0, cj, ck));
                    };
                    st.ym = j == 0 ? zeros : lj > 0 ? st.self - kBrick : across(2, kBrick - 1, lk);
                    st.yp = j + 1 >= bg.ny ? zeros : lj + 1 < kBrick ? st.self + kBrick : across(3, 0, lk);
                    st.zm = k == 0 ? zeros : lk > 0 ? st.self - kBrick * kBrick : across(4, lj, kBrick - 1);
                    st.zp = k + 1 >= bg.nz ? zeros : lk + 1 < kBrick ? st.self + kBrick * kBrick : across(5, lj, 0);
                    st.xm_end = nb[0] == none ? Real(0) : p[nb[0] + std::size_t(BrickGrid::local(kBrick - 1, lj, lk))];
                    st.xp_end = nb[1] == none ? Real(0) : p[nb[1] + std::size_t(BrickGrid::local(0, lj, lk))];
                    // Rows away from the grid boundary (nearly all) have six neighbours everywhere.
                    const bool edge = r.i0 == 0 || r.i0 + kBrick >= bg.nx || j == 0 || j + 1 >= bg.ny || k == 0 ||
                                      k + 1 >= bg.nz;
                    if (edge || !six) {
                        const Real yz = Real(4) - Real(j == 0) - Real(j + 1 >= bg.ny) - Real(k == 0) - Real(k + 1 >= bg.nz);
                        for (int q = 0; q < kBrick; ++q)
                            st.count[q] = yz + Real(2) - Real(q == 0 && r.i0 == 0) - Real(r.i0 + q + 1 >= bg.nx);
                        six = !edge;
                    }
                    if constexpr (std::is_invocable_v<F, std::size_t, int, int, int, const RowStencil<Real>&, std::size_t>)
                        f(row, j, k, r.i0, st, t);
                    else
                        f(row, j, k, r.i0, st);
                }
            done(b, r);
        });
    }

    Hierarchy hier_;
    std::vector<BrickGrid> grids_;
    std::vector<LevelFields<Real>> fields_;
    std::vector<std::uint32_t> coarse_cells_;  // storage positions of the coarsest level's coupled cells
    std::vector<Real> coarse_matrix_, coarse_rhs_;
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
