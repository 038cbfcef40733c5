// stray_points (stray_points.hpp). The cells screen the points first (points_short_of):
// nearly every point has company near it, and only the few lonely ones fit a plane.
#include "geometry/stray_points.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_samples.hpp"

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

// The plane through the mean of the points d (about the point asked about) with the
// least scatter: its unit normal, the mean, and the RMS distance of the points from it.
struct Plane {
    Vec3 normal{0, 0, 1}, mean{0, 0, 0};
    double scatter = 0;
};
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

// Whether point k stands off the plane of its nearest other points (StraySettings). The
// plane is fitted to those of them that are not lonely themselves (when at least half
// are not), so that two strays near each other do not hide each other: one stray in the
// fit tilts a plane over a patch a few spacings wide.
template <class Lonely>
bool stands_off(const PointTree& t, std::uint32_t k, const StraySettings& s, const Lonely& lonely,
                std::vector<Vec3>& d, std::vector<std::uint8_t>& use) {
    const double reach = t.kth_nearest(k, s.neighbours);
    const Vec3 q = t.point(k);
    d.clear();
    use.clear();
    std::size_t company = 0;
    t.for_each_within(q, std::nextafter(reach * reach, std::numeric_limits<double>::infinity()), [&](std::uint32_t j) {
        const Vec3 p = t.point(j);
        const Vec3 r{p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        if (r[0] == 0 && r[1] == 0 && r[2] == 0) return;  // itself, or its own duplicates
        d.push_back(r);
        use.push_back(!lonely(j));
        company += use.back();
    });
    if (d.size() < 3) return false;
    // Where most of them are lonely too (a sparse part of the surface) all of them.
    if (2 * company < d.size()) use.assign(d.size(), 1);
    // Then, a few times, without the one farthest off it while that one lies beyond four
    // times the scatter of the rest: other strays among them (one in a patch a few
    // spacings wide tilts the plane), where a Gaussian scatter would hardly ever go.
    Plane f = fit_plane(d, use);
    for (std::size_t round = 0; round < d.size() / 4; ++round) {
        std::size_t worst = d.size();
        double far = -1;
        for (std::size_t i = 0; i < d.size(); ++i) {
            if (!use[i]) continue;
            const double r = std::abs(f.normal[0] * (d[i][0] - f.mean[0]) + f.normal[1] * (d[i][1] - f.mean[1]) +
                                      f.normal[2] * (d[i][2] - f.mean[2]));
            if (r > far) far = r, worst = i;
        }
        use[worst] = 0;
        const Plane rest = fit_plane(d, use);
        if (!(far > 4 * rest.scatter)) {
            use[worst] = 1;
            break;
        }
        f = rest;
    }
    // q is the origin here.
    const auto height = [&](const Vec3& p) {
        return f.normal[0] * (p[0] - f.mean[0]) + f.normal[1] * (p[1] - f.mean[1]) + f.normal[2] * (p[2] - f.mean[2]);
    };
    const double up = height({0, 0, 0}), off = std::abs(up);
    if (!(off > s.plane_sigmas * f.scatter && off > s.plane_reach * reach)) return false;
    // A point with two neighbours about as high above the plane (on its side, at half its
    // height or more) and nearer to it than half the reach is one of a small feature the
    // surface has, not a stray (two strays near each other are not rare; three are).
    std::size_t raised = 0;
    for (const Vec3& p : d)
        raised += height(p) * up > 0.5 * up * up && p[0] * p[0] + p[1] * p[1] + p[2] * p[2] < 0.25 * reach * reach;
    return raised < 2;
}

}  // namespace

std::vector<std::uint8_t> stray_points(const PointTree& t, const StraySettings& s) {
    const std::size_t n = t.size();
    if (n < s.neighbours + 2) return {};
    // The typical distance to a point's nearest neighbour, over an even sample.
    const std::vector<std::uint32_t> sample = strided_sample(t, s.median_sample);
    std::vector<double> nearest(sample.size());
    const std::ptrdiff_t ns = std::ptrdiff_t(sample.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < ns; ++i) nearest[i] = t.nearest_other(sample[i]);
    std::nth_element(nearest.begin(), nearest.begin() + std::ptrdiff_t(nearest.size() / 2), nearest.end());
    const double typical = nearest[nearest.size() / 2];
    if (!(typical > 0)) return {};
    // Lonely: fewer than `company` other points within `lonely`, for every point at once
    // (points_short_of's flags are count_within's verdicts, point for point): each lonely
    // point's neighbours are looked up, not counted again.
    const double lonely = std::max(s.lonely_factor * typical, s.least_lonely);
    const std::vector<std::uint8_t> alone = points_short_of(t, lonely * lonely, s.company + 1);
    const auto lonely_point = [&](std::uint32_t k) { return alone[k] != 0; };
    std::vector<std::uint8_t> stray(n, 0);
    bool any = false;
    const std::ptrdiff_t nn = std::ptrdiff_t(n);
#pragma omp parallel reduction(|| : any)
    {
        std::vector<Vec3> d;
        std::vector<std::uint8_t> use;
#pragma omp for schedule(dynamic, 1024)
        for (std::ptrdiff_t k = 0; k < nn; ++k)
            if (alone[k] && stands_off(t, std::uint32_t(k), s, lonely_point, d, use))
                stray[k] = 1, any = true;
    }
    if (!any) return {};
    return stray;
}

}  // namespace snvr::detail
