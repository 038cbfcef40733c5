// What the isosurface extractors share: where a grid edge crosses iso, and the
// samples' signs packed 64 to a word so that uniform stretches of the grid are
// skipped a word at a time.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/mesh.hpp"

namespace snvr::contour {

// Fraction of the way from a to b where the interpolant crosses iso.  Exact
// ties and rounding keep it in [0, 1]; NaN or infinite values fall back to 0.5.
inline double crossing(double fa, double fb, double iso) {
    const double t = (iso - fa) / (fb - fa);
    return t >= 0 && t <= 1 ? t : 0.5;
}

// A phase field is tanh of a signed distance: its atanh is linear where the distance is.
inline double unfold(double v) {
    constexpr double edge = 1 - 1e-12;
    return std::atanh(std::clamp(v, -edge, edge));
}

inline double crossing(double fa, double fb, double iso, Interpolation mode) {
    return mode == Interpolation::PhaseField ? crossing(unfold(fa), unfold(fb), unfold(iso)) : crossing(fa, fb, iso);
}

struct Grid {
    int nx, ny, nz;
    int words;  // 64-bit words per row of sign bits
};

// One bit per sample (value > iso), rows of `words` words, so that whole runs
// of uniform samples are tested and skipped 64 at a time. Built a brick at a time: a
// brick's row of 8 samples is one byte of a word, and a stored brick on one side of
// iso throughout (a band field's shared +-1 bricks) fills its bytes without reading.
class SignBits {
public:
    SignBits(const Grid& g, const Field& f, double iso, [[maybe_unused]] bool parallel)
        : g_(g), bits_(std::size_t(g.ny) * g.nz * g.words, 0) {
        static_assert(Field::kBrick == 8, "a brick row is one byte of sign bits");
        const std::vector<std::uint8_t> side = f.precision == Precision::Double ? sides(f.stored_f64(), iso) : sides(f.stored_f32(), iso);
        const int bx = f.bricks_x(), by = f.bricks_y(), bz = f.bricks_z();
#pragma omp parallel for schedule(static) if (parallel)
        for (int kb = 0; kb < bz; ++kb)  // a layer of bricks owns its rows
            for (int jb = 0; jb < by; ++jb)
                for (int ib = 0; ib < bx; ++ib) {
                    const std::uint32_t stored = f.brick_table()[std::size_t(ib) + std::size_t(bx) * (std::size_t(jb) + std::size_t(by) * std::size_t(kb))];
                    const int i0 = ib * 8, cells = std::min(8, g.nx - i0);
                    const std::uint64_t in_grid = (std::uint64_t(1) << cells) - 1;
                    for (int lk = 0; lk < 8 && kb * 8 + lk < g.nz; ++lk)
                        for (int lj = 0; lj < 8 && jb * 8 + lj < g.ny; ++lj) {
                            std::uint64_t byte = side[stored] == kAbove ? 0xffu : 0;
                            if (side[stored] == kMixed) {
                                const std::size_t at = std::size_t(stored) * Field::kBrickCells + std::size_t(8 * (lj + 8 * lk));
                                byte = f.precision == Precision::Double ? row_bits(&f.stored_f64()[at], iso) : row_bits(&f.stored_f32()[at], iso);
                            }
                            bits_[row_start(jb * 8 + lj, kb * 8 + lk) + std::size_t(i0 >> 6)] |= (byte & in_grid) << (i0 & 63);
                        }
                }
    }
    // Word w of row (j, k), read from column offset dx (0 or 1).
    std::uint64_t word(int j, int k, int w, int dx) const {
        const std::uint64_t* row = &bits_[row_start(j, k)];
        if (!dx) return row[w];
        return row[w] >> 1 | (w + 1 < g_.words ? row[w + 1] << 63 : 0);
    }
    // Bits of word w whose column i still has i + dx inside the grid.
    std::uint64_t valid(int w, int dx) const {
        const int limit = g_.nx - dx - 64 * w;
        if (limit >= 64) return ~std::uint64_t(0);
        return limit <= 0 ? 0 : (std::uint64_t(1) << limit) - 1;
    }

private:
    enum Side : std::uint8_t { kBelow, kAbove, kMixed };
    // Each stored brick's side of iso (cells beyond the grid included: a brick called
    // mixed for them is only read cell by cell). The same ordered comparison as the
    // rows: NaN is not above iso.
    template <class T>
    static std::vector<std::uint8_t> sides(const std::vector<T>& values, double iso) {
        std::vector<std::uint8_t> side(values.size() / Field::kBrickCells);
#pragma omp parallel for schedule(static) if (side.size() > 4096)
        for (std::size_t b = 0; b < side.size(); ++b) {
            int above = 0;
            for (int c = 0; c < Field::kBrickCells; ++c) above += double(values[b * Field::kBrickCells + std::size_t(c)]) > iso;
            side[b] = above == 0 ? kBelow : above == Field::kBrickCells ? kAbove : kMixed;
        }
        return side;
    }
    template <class T>
    static std::uint64_t row_bits(const T* v, double iso) {
        std::uint64_t bits = 0;
        for (int b = 0; b < 8; ++b) bits |= std::uint64_t(double(v[b]) > iso) << b;
        return bits;
    }
    std::size_t row_start(int j, int k) const { return (std::size_t(j) + std::size_t(g_.ny) * k) * g_.words; }
    const Grid& g_;
    std::vector<std::uint64_t> bits_;
};

// The field's grid matches the domain's and its values are valid; who: the message's start.
inline void check_field(const Field& field, const Domain& domain, const std::string& who) {
    if (field.nx != domain.nx || field.ny != domain.ny || field.nz != domain.nz)
        throw ParameterError(who + "field is " + std::to_string(field.nx) + "x" + std::to_string(field.ny) + "x" +
                             std::to_string(field.nz) + " but the domain is " + std::to_string(domain.nx) + "x" +
                             std::to_string(domain.ny) + "x" + std::to_string(domain.nz));
    if (field.nx < 0 || field.ny < 0 || field.nz < 0) throw ParameterError(who + "negative grid size");
    field.validate(who);
}

inline int ctz(std::uint64_t x) { return __builtin_ctzll(x); }
// Set bits of x, inline (without a popcnt instruction the builtin is a library call).
inline int popcount(std::uint64_t x) {
    x = x - (x >> 1 & 0x5555555555555555u);
    x = (x & 0x3333333333333333u) + (x >> 2 & 0x3333333333333333u);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
    return int(x * 0x0101010101010101u >> 56);
}

// Appends the per-slab triangle lists in slab order (so the output does not depend
// on the thread count), freeing each list once copied.
template <class Tri>
void concatenate_in_order(std::vector<std::vector<Tri>>& slabs, std::vector<Tri>& out, [[maybe_unused]] bool parallel) {
    std::vector<std::size_t> base(slabs.size() + 1, 0);
    for (std::size_t k = 0; k < slabs.size(); ++k) base[k + 1] = base[k] + slabs[k].size();
    const std::size_t first = out.size();
    out.resize(first + base.back());
#pragma omp parallel for schedule(dynamic) if (parallel)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(slabs.size()); ++k) {
        std::copy(slabs[k].begin(), slabs[k].end(), out.begin() + std::ptrdiff_t(first + base[k]));
        std::vector<Tri>().swap(slabs[k]);
    }
}

}  // namespace snvr::contour
