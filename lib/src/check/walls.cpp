// The walls of a shell (walls.hpp).
#include "check/walls.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "geometry/vec3_math.hpp"
#include "parallel_sizes.hpp"
#include "snvr/error.hpp"
#include "snvr/quality.hpp"
#include "threads_here.hpp"

namespace snvr {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
using Tri = std::array<std::uint32_t, 3>;
}  // namespace

namespace detail {

// vertex_normals(m, faces) without the array of faces, and in parallel: each
// thread sums, in triangle order as vertex_normals does, into its own range of
// vertices, so that every normal comes out the same to the last bit.
std::vector<Vec3> unit_normals(const Mesh& m) {
    const auto& T = m.triangles;
    const std::size_t nv = m.vertices.size();
    std::vector<Vec3> n(nv, Vec3{0, 0, 0});
    const bool parallel = std::ptrdiff_t(T.size()) > detail::kParallelItems;
    const int parts = parallel ? std::max(1, threads_here()) : 1;
#pragma omp parallel for schedule(static, 1) if (parts > 1)
    for (int k = 0; k < parts; ++k) {
        const std::size_t lo = nv * std::size_t(k) / std::size_t(parts), hi = nv * std::size_t(k + 1) / std::size_t(parts);
        for (const Tri& t : T) {
            if ((t[0] < lo || t[0] >= hi) && (t[1] < lo || t[1] >= hi) && (t[2] < lo || t[2] >= hi)) continue;
            const Vec3 f = face_vector(m, t);
            for (std::uint32_t v : t)
                if (v >= lo && v < hi)
                    for (int d = 0; d < 3; ++d) n[v][d] += f[d];
        }
    }
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v) {
        const double len = norm(n[v]);
        if (len > 0)
            for (double& x : n[v]) x /= len;
    }
    return n;
}

// A ray's t_min for the walls: far below any wall, far above the rounding of a
// hit at the ray's own start.
double wall_epsilon(const Mesh& m) {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    for (const Vec3& p : m.vertices)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
        }
    return m.vertices.empty() ? 0 : wall_epsilon(lo, hi);
}

double wall_epsilon(const Vec3& lo, const Vec3& hi) { return 1e-9 * norm({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}); }

// wall[v], v in [first, last): the distance from vertex v along its inward
// normal to the first triangle met, ignoring the vertex's own triangles;
// infinity when nothing is met.
void wall_thickness(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals, double eps,
                    const std::vector<std::uint32_t>& order, std::size_t first, std::size_t last,
                    std::vector<double>& wall, const std::uint8_t* skip) {
    for (std::size_t k = first; k < last; ++k) {
        const std::uint32_t v = order[k];
        if (skip && skip[v]) continue;
        const Vec3& n = normals[v];
        if (dot(n, n) == 0) continue;
        wall[v] = grid.first_hit(m.vertices[v], {-n[0], -n[1], -n[2]}, eps, std::uint32_t(v)).t;
    }
}

std::vector<std::uint32_t> wall_order(const Mesh& m) {
    constexpr int kBits = 6;  // blocks an axis: 2^kBits
    constexpr std::size_t kBlocks = std::size_t(1) << (3 * kBits);
    const std::size_t nv = m.vertices.size();
    if (nv >= std::numeric_limits<std::uint32_t>::max()) throw ResourceError("the walls: more than 2^32 vertices");
    const Bounds box = bounds(m.vertices);
    const Vec3& lo = box.lo;
    const double extent = box.longest();
    const double scale = extent > 0 ? double(1 << kBits) / extent : 0;
    const auto block = [&](const Vec3& p) {
        std::uint32_t c[3];
        for (int d = 0; d < 3; ++d) {  // non-finite coordinates (none in a checked mesh) go to block 0
            const double x = (p[d] - lo[d]) * scale;
            c[d] = x > 0 ? std::uint32_t(std::min(x, double((1 << kBits) - 1))) : 0;
        }
        std::uint32_t key = 0;
        for (int b = kBits - 1; b >= 0; --b)
            for (int d = 2; d >= 0; --d) key = key << 1 | (c[d] >> b & 1);
        return key;
    };
    // A counting sort by block: linear, and in vertex order within a block.
    std::vector<std::uint32_t> keys(nv), start(kBlocks + 1, 0), order(nv);
    for (std::size_t v = 0; v < nv; ++v) ++start[(keys[v] = block(m.vertices[v])) + 1];
    for (std::size_t b = 0; b < kBlocks; ++b) start[b + 1] += start[b];
    for (std::size_t v = 0; v < nv; ++v) order[start[keys[v]]++] = std::uint32_t(v);
    return order;
}

}  // namespace detail

}  // namespace snvr
