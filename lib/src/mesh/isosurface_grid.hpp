// What the isosurface extractors share: where a grid edge crosses iso, read access
// to either field precision, and the samples' signs packed 64 to a word so that
// uniform stretches of the grid are skipped a word at a time.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// Read access to either storage precision without copying the field.
struct Samples {
    const double* f64 = nullptr;
    const float* f32 = nullptr;
    double operator[](std::size_t n) const { return f64 ? f64[n] : double(f32[n]); }
};

struct Grid {
    int nx, ny, nz;
    int words;  // 64-bit words per row of sign bits
    std::size_t at(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k));
    }
};

// One bit per sample (value > iso), rows of `words` words, so that whole runs
// of uniform samples are tested and skipped 64 at a time.
class SignBits {
public:
    SignBits(const Grid& g, const Samples& s, double iso, [[maybe_unused]] bool parallel)
        : g_(g), bits_(std::size_t(g.ny) * g.nz * g.words, 0) {
#pragma omp parallel for schedule(static) if (parallel)
        for (int k = 0; k < g.nz; ++k)
            for (int j = 0; j < g.ny; ++j) {
                std::uint64_t* row = &bits_[row_start(j, k)];
                const std::size_t base = g.at(0, j, k);
                if (s.f64)
                    pack(s.f64 + base, g.nx, iso, row);
                else
                    pack(s.f32 + base, g.nx, iso, row);
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
    // One row's bits, a word at a time without branches. Reading the field is most of
    // an extraction's memory traffic: doubles are compared two at a time where SSE2 is
    // there (the same ordered comparison: NaN is not above iso).
    template <class T>
    static void pack(const T* v, int n, double iso, std::uint64_t* row) {
        int i = 0;
#if defined(__SSE2__)
        if constexpr (std::is_same_v<T, double>) {
            const __m128d limit = _mm_set1_pd(iso);
            for (; i + 64 <= n; i += 64) {
                std::uint64_t bits = 0;
                for (int b = 0; b < 64; b += 2)
                    bits |= std::uint64_t(_mm_movemask_pd(_mm_cmpgt_pd(_mm_loadu_pd(v + i + b), limit))) << b;
                row[i >> 6] = bits;
            }
        }
#endif
        for (; i < n; i += 64) {
            const int m = std::min(64, n - i);
            std::uint64_t bits = 0;
            for (int b = 0; b < m; ++b) bits |= std::uint64_t(double(v[i + b]) > iso) << b;
            row[i >> 6] = bits;
        }
    }
    std::size_t row_start(int j, int k) const { return (std::size_t(j) + std::size_t(g_.ny) * k) * g_.words; }
    const Grid& g_;
    std::vector<std::uint64_t> bits_;
};

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
