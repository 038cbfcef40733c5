// The few vector operations the geometry code needs, in one place.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "snvr/geometry.hpp"

namespace snvr {

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// The box of a set of points (both corners at the origin for none).
struct Bounds {
    Vec3 lo{0, 0, 0}, hi{0, 0, 0};
    double extent(int a) const { return hi[a] - lo[a]; }
    double longest() const { return std::max({extent(0), extent(1), extent(2)}); }
};
inline Bounds bounds(const std::vector<Vec3>& points) {
    if (points.empty()) return {};
    Bounds b{points[0], points[0]};
    for (const Vec3& p : points)
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::min(b.lo[a], p[a]);
            b.hi[a] = std::max(b.hi[a], p[a]);
        }
    return b;
}

// round_centre (geometry.hpp) of a box rather than of its points.
Vec3 round_centre(const Bounds& box);

// Twice the triangle's area times its unit normal, from the counter-clockwise order.
inline Vec3 face_vector(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    return cross(sub(b, a), sub(c, a));
}

// Unit vertex normals: the area-weighted mean of the incident faces' normals
// (zero for a vertex no proper triangle uses).
inline std::vector<Vec3> vertex_normals(const Mesh& m, const std::vector<Vec3>& faces) {
    std::vector<Vec3> n(m.vertices.size(), Vec3{0, 0, 0});
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (std::uint32_t v : m.triangles[t])
            for (int d = 0; d < 3; ++d) n[v][d] += faces[t][d];
    for (Vec3& v : n) {
        const double len = norm(v);
        if (len > 0)
            for (double& x : v) x /= len;
    }
    return n;
}

}  // namespace snvr
