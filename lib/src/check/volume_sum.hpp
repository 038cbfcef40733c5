// Six times the volume a mesh encloses, summed the same in any order: each triangle's
// tetrahedron about the centre of the mesh's box is rounded to a fixed quantum and added as
// an integer. So a mesh held in slabs by several processes sums each slab's part and adds
// those, and gets the whole mesh's sum to the bit (a sum of doubles depends on its order),
// as every piece's sum does. The quantum is 2^-84 of a power of two above the box's longest
// side cubed; no term exceeds 0.65 of that cube (|a| |b| |c| with each corner within half
// the box's diagonal of its centre), so a term takes fewer than 84 bits and 2^32 of them
// fewer than 117 of the 127; rounding moves the sum by at most 2^-52 of the cube.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "snvr/geometry.hpp"

namespace snvr::detail {

__extension__ typedef __int128 ExactSum;

class VolumeSum {
public:
    // About the centre of the box [lo, hi] (the whole mesh's, at every process alike).
    VolumeSum(const Vec3& lo, const Vec3& hi) {
        double longest = 0;
        for (int a = 0; a < 3; ++a) {
            centre_[a] = 0.5 * (lo[a] + hi[a]);
            longest = std::max(longest, hi[a] - lo[a]);
        }
        const double cube = longest * longest * longest;
        scale_ = cube > 0 && std::isfinite(cube) ? std::ldexp(1.0, kBits - std::ilogb(cube) - 1) : 1;
    }
    // Six times the signed volume of the tetrahedron (centre, A, B, C), rounded to the
    // quantum, in quanta (0 where it is not finite: the sum says so instead).
    ExactSum term(const Vec3& A, const Vec3& B, const Vec3& C, bool& finite) const {
        const double a0 = A[0] - centre_[0], a1 = A[1] - centre_[1], a2 = A[2] - centre_[2];
        const double b0 = B[0] - centre_[0], b1 = B[1] - centre_[1], b2 = B[2] - centre_[2];
        const double c0 = C[0] - centre_[0], c1 = C[1] - centre_[1], c2 = C[2] - centre_[2];
        const double six = a0 * (b1 * c2 - b2 * c1) + a1 * (b2 * c0 - b0 * c2) + a2 * (b0 * c1 - b1 * c0);
        const double x = six * scale_;  // a power of two: exact
        if (!(std::fabs(x) < 0x1p85)) {
            finite = false;
            return 0;
        }
        // Its upper bits apart (the product truncated: exact, under 2^43), then the lower
        // 42 (exact: a multiple of x's last place), rounded to the nearest (ties to even)
        // by adding and taking away 1.5 x 2^52.
        const auto high = std::int64_t(x * 0x1p-42);
        const double low = x - double(high) * 0x1p42;
        const double rounded = (low + 0x1.8p52) - 0x1.8p52;
        return ExactSum(high) * (ExactSum(1) << 42) + ExactSum(std::int64_t(rounded));
    }
    // Six times the volume of a sum of terms.
    double six_volume(ExactSum sum) const { return double(sum) / scale_; }

private:
    static constexpr int kBits = 84;
    Vec3 centre_{0, 0, 0};
    double scale_ = 1;
};

}  // namespace snvr::detail
