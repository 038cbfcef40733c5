// stray_points (stray_points.hpp). The cells screen the points first (points_short_of):
// nearly every point has company near it, and only the few lonely ones fit a plane.
#include "geometry/stray_points.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/local_plane.hpp"
#include "geometry/neighbour_counts.hpp"
#include "geometry/point_samples.hpp"
#include "geometry/vec3_math.hpp"

namespace snvr::detail {

namespace {

// Whether point k stands off the plane of its nearest other points (StraySettings). The
// plane is fitted to those of them that are not lonely themselves (when at least half
// are not), so that two strays near each other do not hide each other: one stray in the
// fit tilts a plane over a patch a few spacings wide.
// complete(k, reach): whether t holds every point of the cloud within reach of point k
// (else the point is left undecided).
enum Verdict : std::uint8_t { kStays = 0, kStray = 1, kUndecided = 2 };
template <class Lonely, class Complete>
Verdict stands_off(const PointTree& t, std::uint32_t k, const StraySettings& s, const Lonely& lonely,
                   const Complete& complete, std::vector<PointTree::Neighbour>& near, std::vector<Vec3>& d,
                   std::vector<std::uint8_t>& use) {
    const double reach = t.kth_nearest(k, s.neighbours, &near);
    if (!complete(k, reach)) return kUndecided;
    const double within = std::nextafter(reach * reach, std::numeric_limits<double>::infinity());
    const Vec3 q = t.point(k);
    d.clear();
    use.clear();
    std::size_t company = 0;
    for (const PointTree::Neighbour& at : near) {  // in tree order, as for_each_within gives them
        if (!(at.dist_sq < within)) continue;
        const Vec3 p = t.point(at.index);
        const Vec3 r{p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        if (r[0] == 0 && r[1] == 0 && r[2] == 0) continue;  // itself, or its own duplicates
        d.push_back(r);
        use.push_back(!lonely(at.index));
        company += use.back();
    }
    if (d.size() < 3) return kStays;
    // Where most of them are lonely too (a sparse part of the surface) all of them.
    if (2 * company < d.size()) use.assign(d.size(), 1);
    // Every plane below passes through the mean of the points it is fitted to, so q (the
    // origin) lies within that mean's length of it; the rounds drop at most d.size() / 4 of
    // them, none farther than the reach. Where even so the mean stays nearer q than
    // plane_reach x reach (a tenth to spare for rounding), q cannot stand off: no plane is
    // fitted (most lonely points of a sparse scan, 0.7 us each).
    {
        Vec3 sum{0, 0, 0};
        std::size_t used = 0;
        for (std::size_t i = 0; i < d.size(); ++i)
            if (use[i]) sum = {sum[0] + d[i][0], sum[1] + d[i][1], sum[2] + d[i][2]}, ++used;
        const std::size_t drops = d.size() / 4;
        if (used > drops &&
            norm(sum) + double(drops) * reach < 0.9 * s.plane_reach * reach * double(used - drops))
            return kStays;
    }
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
    if (!(off > s.plane_sigmas * f.scatter && off > s.plane_reach * reach)) return kStays;
    // A point with two neighbours about as high above the plane (on its side, at half its
    // height or more) and nearer to it than half the reach is one of a small feature the
    // surface has, not a stray (two strays near each other are not rare; three are).
    std::size_t raised = 0;
    for (const Vec3& p : d)
        raised += height(p) * up > 0.5 * up * up && p[0] * p[0] + p[1] * p[1] + p[2] * p[2] < 0.25 * reach * reach;
    return raised < 2 ? kStray : kStays;
}

// The verdicts of the points place(i), i < count: the lonely ones tested, in threads
// (told how far they have come where asked: 6.7 s for the 5.5 M lonely points of the
// 12.5 M-point city block on two threads).
template <class Place, class Complete>
std::vector<std::uint8_t> verdicts(const PointTree& t, const StraySettings& s, const std::vector<std::uint8_t>& alone,
                                   std::size_t count, const Place& place, const Complete& complete,
                                   const Told& told = nullptr) {
    std::vector<std::uint8_t> out(count, kStays);
    const auto lonely_point = [&](std::uint32_t k) { return alone[k] != 0; };
    in_told_pieces(count, told, [&](std::size_t begin, std::size_t end) {
#pragma omp parallel
        {
            std::vector<PointTree::Neighbour> near;
            std::vector<Vec3> d;
            std::vector<std::uint8_t> use;
#pragma omp for schedule(dynamic, 1024)
            for (std::ptrdiff_t i = std::ptrdiff_t(begin); i < std::ptrdiff_t(end); ++i) {
                const std::uint32_t k = place(std::size_t(i));
                if (alone[k]) out[std::size_t(i)] = stands_off(t, k, s, lonely_point, complete, near, d, use);
            }
        }
    });
    return out;
}

}  // namespace

std::vector<std::uint8_t> stray_points(const PointTree& t, const StraySettings& s, const ShortOf& short_of,
                                       const AskStrays& ask, const Told& told) {
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
    const std::vector<std::uint8_t> alone =
        short_of ? short_of(t, lonely * lonely, s.company + 1) : points_short_of(t, lonely * lonely, s.company + 1);
    const StraysElsewhere elsewhere = ask ? ask(t, s, alone) : StraysElsewhere{n, nullptr};
    const auto whole = [](std::uint32_t, double) { return true; };
    std::vector<std::uint8_t> stray =
        verdicts(t, s, alone, elsewhere.here_end, [](std::size_t i) { return std::uint32_t(i); }, whole, told);
    stray.resize(n, kStays);
    if (elsewhere.collect) {
        std::vector<std::uint32_t> undecided;
        elsewhere.collect(stray, undecided);
        const std::vector<std::uint8_t> got =
            verdicts(t, s, alone, undecided.size(), [&](std::size_t i) { return undecided[i]; }, whole);
        for (std::size_t i = 0; i < undecided.size(); ++i) stray[undecided[i]] = got[i];
    }
    if (std::find(stray.begin(), stray.end(), kStray) == stray.end()) return {};
    return stray;
}

RangeStrays range_strays(const PointTree& range, const StraySettings& s, const std::vector<std::uint8_t>& alone,
                         std::uint64_t keys_lo, std::uint64_t keys_hi, int rounding_cells) {
    const PointTree::Frame& frame = range.frame();
    const double margin = rounding_cells / frame.scale;
    const auto complete = [&](std::uint32_t k, double reach) {
        const Vec3f& x = range.xyz[k];
        const double r = reach + margin;
        return frame.key(Vec3{x[0] - r, x[1] - r, x[2] - r}) >= keys_lo &&
               frame.key(Vec3{x[0] + r, x[1] + r, x[2] + r}) < keys_hi;
    };
    const std::vector<std::uint8_t> got =
        verdicts(range, s, alone, range.size(), [](std::size_t i) { return std::uint32_t(i); }, complete);
    RangeStrays out;
    for (std::size_t k = 0; k < got.size(); ++k)
        if (got[k] != kStays) (got[k] == kStray ? out.strays : out.undecided).push_back(std::uint32_t(k));
    return out;
}

}  // namespace snvr::detail
