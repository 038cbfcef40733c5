// fit_plane (local_plane.hpp): the covariance of the points and its least eigenvector;
// plane_axes; fit_quadric by its normal equations; local_patch.
#include "geometry/local_plane.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/vec3_math.hpp"

namespace snvr::detail {

namespace {

// The smallest eigenvalue of the symmetric matrix a (destroyed) and a unit eigenvector
// of it, by cyclic Jacobi rotations.
void smallest_eigen(double (&a)[3][3], double& value, Vec3& vector) {
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (!(off > 1e-30 * diag)) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double kp = a[k][p], kq = a[k][q];
                    a[k][p] = c * kp - s * kq;
                    a[k][q] = s * kp + c * kq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double pk = a[p][k], qk = a[q][k];
                    a[p][k] = c * pk - s * qk;
                    a[q][k] = s * pk + c * qk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double kp = v[k][p], kq = v[k][q];
                    v[k][p] = c * kp - s * kq;
                    v[k][q] = s * kp + c * kq;
                }
            }
    }
    int least = 0;
    for (int i = 1; i < 3; ++i)
        if (a[i][i] < a[least][least]) least = i;
    value = a[least][least];
    vector = {v[0][least], v[1][least], v[2][least]};
}

// Solves the 6 x 6 system m x = r (m destroyed) by elimination with partial pivoting;
// false when it is singular.
bool solve6(double (&m)[6][6], double (&r)[6], double (&x)[6]) {
    for (int c = 0; c < 6; ++c) {
        int pivot = c;
        for (int i = c + 1; i < 6; ++i)
            if (std::fabs(m[i][c]) > std::fabs(m[pivot][c])) pivot = i;
        if (!(std::fabs(m[pivot][c]) > 1e-12)) return false;
        std::swap(m[c], m[pivot]);
        std::swap(r[c], r[pivot]);
        for (int i = c + 1; i < 6; ++i) {
            const double f = m[i][c] / m[c][c];
            for (int j = c; j < 6; ++j) m[i][j] -= f * m[c][j];
            r[i] -= f * r[c];
        }
    }
    for (int c = 5; c >= 0; --c) {
        double s = r[c];
        for (int j = c + 1; j < 6; ++j) s -= m[c][j] * x[j];
        x[c] = s / m[c][c];
    }
    return true;
}

}  // namespace

Plane fit_plane(const std::vector<Vec3>& d, const std::vector<std::uint8_t>& use) {
    double sum[3] = {0, 0, 0}, prod[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    std::size_t count = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        if (!use[i]) continue;
        ++count;
        for (int a = 0; a < 3; ++a) {
            sum[a] += d[i][a];
            for (int b = 0; b < 3; ++b) prod[a][b] += d[i][a] * d[i][b];
        }
    }
    Plane f;
    if (count == 0) return f;
    double cov[3][3];
    for (int a = 0; a < 3; ++a) f.mean[a] = sum[a] / double(count);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) cov[a][b] = prod[a][b] / double(count) - f.mean[a] * f.mean[b];
    double variance;
    smallest_eigen(cov, variance, f.normal);
    f.scatter = std::sqrt(std::max(0.0, variance));
    return f;
}

bool fit_quadric(const std::vector<std::array<double, 3>>& uvw, Quadric& quadric) {
    if (uvw.size() < 6) return false;
    double m[6][6] = {}, r[6] = {};
    for (const auto& q : uvw) {
        const double basis[6] = {q[0] * q[0], q[0] * q[1], q[1] * q[1], q[0], q[1], 1};
        for (int i = 0; i < 6; ++i) {
            r[i] += basis[i] * q[2];
            for (int j = 0; j < 6; ++j) m[i][j] += basis[i] * basis[j];
        }
    }
    return solve6(m, r, quadric.coef);
}

namespace {

// The largest square whose root is at most r: square roots are correctly rounded, so a
// squared distance d passes d <= it exactly where sqrt(d) <= r.
double largest_square_within(double r) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double x = r * r;
    while (x > 0 && std::sqrt(x) > r) x = std::nextafter(x, 0.0);
    for (double up = std::nextafter(x, kInf); up < kInf && std::sqrt(up) <= r; up = std::nextafter(x, kInf)) x = up;
    return x;
}

}  // namespace

LocalPatch local_patch(const PointTree& tree, std::uint32_t k, std::size_t neighbours, std::size_t plane_of,
                       double off_plane, int refits, double within_only) {
    LocalPatch patch;
    const Vec3 p = tree.point(k);
    // Whether none lies farther than within_only is a count that stops at enough, not the
    // search: its nearest neighbours + 1 (itself and any duplicates counted, as the search
    // counts them) within that distance exactly where sqrt(dist_sq) <= within_only (the
    // 48 nearest of four in five points of a dense scan's cut, at the holes' search).
    if (within_only >= 0 && tree.count_within(p, largest_square_within(within_only), neighbours + 1) > neighbours)
        return patch;
    std::vector<Vec3> d;
    for (const auto& at : tree.nearest_points(p, neighbours + 1))
        if (at.dist_sq > 0) {
            d.push_back(sub(tree.point(at.index), p));
            patch.distance.push_back(std::sqrt(at.dist_sq));
        }
    if (within_only >= 0 && !patch.distance.empty() && !(patch.distance.back() > within_only)) return patch;
    std::vector<std::uint8_t> nearest(d.size(), 0);
    std::fill(nearest.begin(), nearest.begin() + std::ptrdiff_t(std::min(d.size(), plane_of)), 1);
    patch.normal = fit_plane(d, nearest).normal;
    // The plane of the nearest few sees one sheet; all those near it, that sheet at large.
    for (int pass = 0; pass < refits; ++pass) {
        std::vector<std::uint8_t> near_plane(d.size(), 0);
        std::size_t kept = 0;
        for (std::size_t i = 0; i < d.size(); ++i) {
            near_plane[i] = std::fabs(dot(d[i], patch.normal)) <= off_plane * norm(d[i]);
            kept += near_plane[i];
        }
        if (kept < 6 || near_plane == nearest) break;
        nearest = near_plane;
        patch.normal = fit_plane(d, nearest).normal;
    }
    const Vec3 n = patch.normal;
    plane_axes(n, patch.e1, patch.e2);
    for (const Vec3& v : d)
        if (std::fabs(dot(v, n)) <= off_plane * norm(v))
            patch.uvw.push_back({dot(v, patch.e1), dot(v, patch.e2), dot(v, n)});
    return patch;
}

void plane_axes(const Vec3& n, Vec3& e1, Vec3& e2) {
    e1 = cross(n, std::fabs(n[0]) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
    const double length = norm(e1);
    for (double& x : e1) x /= length;
    e2 = cross(n, e1);
}

}  // namespace snvr::detail
