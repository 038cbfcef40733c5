// share_bordering_holes and hole_centres (sampling_holes.hpp): each point's neighbours
// seen in their plane, the empty discs through the point in 32 directions, refined to the
// exact circles through the point and the two neighbours that bound them.
#include "geometry/sampling_holes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/flat_hull.hpp"
#include "geometry/local_plane.hpp"
#include "geometry/point_samples.hpp"
#include "geometry/vec3_math.hpp"
#include "parallel_sizes.hpp"
#include "snvr/error.hpp"

namespace snvr {
namespace {

using detail::Flat;


constexpr std::size_t kNeighbours = 48;  // enough to enclose the widest hole of a random sampling of 20,000
constexpr std::size_t kPlaneNeighbours = 16;
constexpr double kOffPlane = 0.75;  // sin of the steepest a neighbour stands off the plane (49 degrees)
constexpr double kWidestGap = 0.9 * M_PI;  // radians: the widest empty angle around a hole's centre
constexpr double kRim = 0.05;              // points within 5% of a hole's radius beyond its rim are on it
constexpr double kFlatness = 0.1;          // a centre's distance to its nearest point within 10% of its radius
constexpr int kDirections = 32;

// A point's neighbours in their plane, the point at the origin, and how far they reach.
struct Neighbourhood {
    std::vector<Flat> q;
    std::vector<double> height;  // of each above the plane
    std::vector<double> square;  // |q|^2
    Vec3 e1{0, 0, 0}, e2{0, 0, 0}, normal{0, 0, 1};  // the plane's axes and normal
    double reach = 0;

    // The disc centred at c through the origin, if empty of q, enclosed and within reach.
    bool holds_hole(const Flat& c) const {
        const double r_sq = c[0] * c[0] + c[1] * c[1];
        if (!(4 * r_sq <= reach * reach)) return false;  // wider than the neighbours can judge
        for (const Flat& p : q) {
            const double dx = p[0] - c[0], dy = p[1] - c[1];
            if (dx * dx + dy * dy < r_sq * (1 - 1e-9)) return false;
        }
        return detail::strictly_inside(hull(), c) && surrounded(c, std::sqrt(r_sq));
    }
    // The convex hull of q and the origin, made when first asked (most points' discs end
    // before it is: a scan's 48 neighbours' hull cost a fifth of the search).
    const std::vector<Flat>& hull() const {
        if (hull_.empty()) {
            std::vector<Flat> all = q;
            all.push_back({0, 0});
            hull_ = detail::convex_hull(std::move(all));
        }
        return hull_;
    }
    // Whether the points near the disc (within twice its radius of its centre) surround
    // it, leaving no empty angle wider than kWidestGap seen from the centre: a hole in a
    // sampling has points all round; a notch in a ragged boundary opens to one side.
    bool surrounded(const Flat& c, double r) const {
        std::vector<double> angles{std::atan2(-c[1], -c[0])};  // the point itself
        for (const Flat& p : q) {
            const double dx = p[0] - c[0], dy = p[1] - c[1];
            if (dx * dx + dy * dy <= 4 * r * r) angles.push_back(std::atan2(dy, dx));
        }
        std::sort(angles.begin(), angles.end());
        double widest = angles.front() + 2 * M_PI - angles.back();
        for (std::size_t i = 1; i < angles.size(); ++i) widest = std::max(widest, angles[i] - angles[i - 1]);
        return widest < kWidestGap;
    }
    // The neighbours as (u, v, height), the point itself among them.
    std::vector<std::array<double, 3>> uvw() const {
        std::vector<std::array<double, 3>> out{{0, 0, 0}};
        for (std::size_t i = 0; i < q.size(); ++i) out.push_back({q[i][0], q[i][1], height[i]});
        return out;
    }
    // The height above the plane at c of the plane through the points on the rim of the
    // disc of radius r centred there (the point itself among them); false where they
    // scatter about that plane by more than kFlatness r (not one flat patch: a twisted or
    // folded surface) or it stands steeply on this one.
    bool rim_height(const Flat& c, double r, double& height_at_c) const {
        std::vector<Vec3> rim{{0, 0, 0}};
        for (std::size_t i = 0; i < q.size(); ++i) {
            const double dx = q[i][0] - c[0], dy = q[i][1] - c[1];
            if (dx * dx + dy * dy <= (1 + kRim) * (1 + kRim) * r * r) rim.push_back({q[i][0], q[i][1], height[i]});
        }
        const detail::Plane plane = detail::fit_plane(rim, std::vector<std::uint8_t>(rim.size(), 1));
        if (!(plane.scatter <= kFlatness * r) || !(std::fabs(plane.normal[2]) >= 0.5)) return false;
        const Vec3& m = plane.mean;
        height_at_c = m[2] - (plane.normal[0] * (c[0] - m[0]) + plane.normal[1] * (c[1] - m[1])) / plane.normal[2];
        return true;
    }
    // Whether the centre at c, at_c above the plane, is about r from each point on the
    // rim in space too: a height the rim does not bear out (a quadric bent by a twisted
    // surface's other turns) would put the point off the surface.
    bool rim_equidistant(const Flat& c, double r, double at_c) const {
        const double most = (1 + kRim + kFlatness) * r;
        if (!(c[0] * c[0] + c[1] * c[1] + at_c * at_c <= most * most)) return false;  // the point itself
        for (std::size_t i = 0; i < q.size(); ++i) {
            const double dx = q[i][0] - c[0], dy = q[i][1] - c[1], dz = height[i] - at_c;
            if (dx * dx + dy * dy <= (1 + kRim) * (1 + kRim) * r * r && !(dx * dx + dy * dy + dz * dz <= most * most))
                return false;
        }
        return true;
    }
    // For each direction u[d]: the disc through the origin whose centre lies along it,
    // grown until a neighbour meets its rim: that neighbour (by[d]; q.size(): none) and the
    // distance to the centre (rho[d]), |q|^2 / (2 q.u) least over the neighbours ahead
    // (compared as fractions: no division each; the first of equals). The directions side
    // by side for each neighbour: each direction's comparisons in the neighbours' order,
    // as one direction at a time made them, but not each waiting on the last.
    template <std::size_t D>
    void blocking(const std::array<Flat, D>& u, std::size_t (&by)[D], double (&rho)[D]) const {
        double ux[D], uy[D], num[D], den[D];  // the least so far, num / den; none: 1 / 0
        for (std::size_t d = 0; d < D; ++d) ux[d] = u[d][0], uy[d] = u[d][1], num[d] = 1, den[d] = 0, by[d] = q.size();
        for (std::size_t i = 0; i < q.size(); ++i) {
            const double x = q[i][0], y = q[i][1], s = square[i];
            for (std::size_t d = 0; d < D; ++d) {
                const double along = 2 * (x * ux[d] + y * uy[d]);
                const bool nearer = along > 0 && s * den[d] < num[d] * along;
                num[d] = nearer ? s : num[d];
                den[d] = nearer ? along : den[d];
                by[d] = nearer ? i : by[d];
            }
        }
        for (std::size_t d = 0; d < D; ++d)
            rho[d] = by[d] == q.size() ? std::numeric_limits<double>::infinity() : num[d] / den[d];
    }

private:
    mutable std::vector<Flat> hull_;
};

// Point k's neighbourhood, none (no neighbours) where it can hold no hole wider than
// `least`: a hole's disc is at most half the neighbours' reach across (holds_hole), so
// where they all lie within 2 least none is (four in five points of a dense scan's cut at
// the hole size of 2 voxels, whose plane and discs then need not be made).
Neighbourhood neighbourhood(const detail::PointTree& tree, std::uint32_t k, double least) {
    Neighbourhood n;
    // The plane of the nearest few: over all 48 a curved or twisted surface (a helicoid
    // near its axis) can be seen edge on, and its points then leave false holes between them.
    const detail::LocalPatch patch = detail::local_patch(tree, k, kNeighbours, kPlaneNeighbours, kOffPlane, 0, 2 * least);
    if (patch.distance.size() < 8 || !(patch.distance.back() > 2 * least)) return n;
    n.reach = patch.distance.back();
    n.normal = patch.normal;
    n.e1 = patch.e1;
    n.e2 = patch.e2;
    for (const auto& v : patch.uvw) {
        n.q.push_back({v[0], v[1]});
        n.height.push_back(v[2]);
        n.square.push_back(v[0] * v[0] + v[1] * v[1]);
    }
    return n;
}

// The centre of the circle through the origin, a and b (none when they are in line).
bool circle_centre(const Flat& a, const Flat& b, Flat& c) {
    const double det = 2 * (a[0] * b[1] - a[1] * b[0]);
    if (det == 0) return false;
    const double aa = a[0] * a[0] + a[1] * a[1], bb = b[0] * b[0] + b[1] * b[1];
    c = {(aa * b[1] - bb * a[1]) / det, (bb * a[0] - aa * b[0]) / det};
    return true;
}

struct Hole {
    double radius = 0;
    Vec3 centre{0, 0, 0};
};

// The holes at point k wider than `least`, widest first (a point on the rims of two
// holes sees both): the discs through the point in 32 directions, and the circles
// through the point and the neighbours bounding two directions side by side (where a
// hole is widest), each kept when it is a hole and not the same as a wider one kept.
// With `first` the widest alone.
std::vector<Hole> holes_at(const detail::PointTree& tree, std::uint32_t k, double least, bool first) {
    std::vector<Hole> holes;
    const Neighbourhood n = neighbourhood(tree, k, least);
    if (n.q.size() < 8) return holes;
    static const std::array<Flat, kDirections> directions = [] {
        std::array<Flat, kDirections> u;
        for (int i = 0; i < kDirections; ++i) u[std::size_t(i)] = {std::cos(2 * M_PI * i / kDirections), std::sin(2 * M_PI * i / kDirections)};
        return u;
    }();
    std::size_t by[kDirections];
    double rho[kDirections];
    n.blocking(directions, by, rho);
    std::vector<std::pair<double, Flat>> candidates;  // radius, centre
    for (int i = 0; i < kDirections; ++i) {
        if (by[i] == n.q.size()) continue;  // open that way
        const Flat& u = directions[std::size_t(i)];
        if (rho[i] > least) candidates.push_back({rho[i], {rho[i] * u[0], rho[i] * u[1]}});
        const int j = (i + 1) % kDirections;
        Flat c;
        if (by[j] != n.q.size() && by[j] != by[i] && circle_centre(n.q[by[i]], n.q[by[j]], c)) {
            const double r = std::sqrt(c[0] * c[0] + c[1] * c[1]);
            if (r > least) candidates.push_back({r, c});
        }
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const Vec3 p = tree.point(k);
    bool fitted = false, curved = false;
    detail::Quadric surface;
    std::vector<Flat> rejected;  // centres found no hole: a candidate near one is the same disc
    const auto near_rejected = [&rejected](const Flat& c, double radius) {
        return std::any_of(rejected.begin(), rejected.end(), [&](const Flat& r) {
            return (r[0] - c[0]) * (r[0] - c[0]) + (r[1] - c[1]) * (r[1] - c[1]) < 0.01 * radius * radius;
        });
    };
    for (const auto& [radius, c] : candidates) {
        if (near_rejected(c, radius)) continue;
        Hole hole{radius, {}};
        // At the height of the points on its rim: on a curved surface the plane through
        // the point stands off it, by radius^2 / 2R on a sphere of radius R.
        double h = 0;
        if (!n.rim_height(c, radius, h)) {
            rejected.push_back(c);
            continue;
        }
        // On the surface the neighbours describe, curved (a torus's tube, a sphere): the rim's
        // plane cuts inside it by the rim's sagitta.
        if (!fitted) {
            fitted = true;
            curved = detail::fit_quadric(n.uvw(), surface);
        }
        if (curved) h = surface.at(c[0], c[1]);
        if (!n.rim_equidistant(c, radius, h)) {
            rejected.push_back(c);
            continue;
        }
        for (int a = 0; a < 3; ++a) hole.centre[a] = p[a] + c[0] * n.e1[a] + c[1] * n.e2[a] + h * n.normal[a];
        const auto same = [&](const Hole& h) { return norm(sub(h.centre, hole.centre)) < 0.5 * h.radius; };
        if (std::any_of(holes.begin(), holes.end(), same)) continue;
        if (!n.holds_hole(c)) {
            rejected.push_back(c);
            continue;
        }
        // On a flat patch the centre lies about `radius` from its nearest point in space
        // too; where the plane does not follow the surface (an edge, a fold) it does not.
        const double nearest = std::sqrt(tree.nearest(hole.centre).dist_sq);
        if (!(nearest >= (1 - kFlatness) * radius && nearest <= (1 + kFlatness) * radius)) continue;
        holes.push_back(hole);
        if (first) break;
    }
    return holes;
}

// One centre per hole of `holes`, widest first: a centre nearer than half its radius to
// a wider one's is the same hole seen from another of its rim's points.
PointSet distinct_centres(std::vector<Hole> holes, double least) {
    // Widest first, ties by place: the same centres whatever order the threads took.
    std::sort(holes.begin(), holes.end(), [](const Hole& a, const Hole& b) {
        return a.radius != b.radius ? a.radius > b.radius : a.centre < b.centre;
    });
    // The centres kept so far, filed in cubes of half the least radius: a hole of radius
    // r looks r / 2 around its centre, a few cubes each way.
    const double cube = 0.5 * least;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> filed;
    const auto cell = [cube](double x) { return std::int64_t(std::floor(x / cube)); };
    const auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
        return (std::uint64_t(i & 0x1FFFFF) << 42) | (std::uint64_t(j & 0x1FFFFF) << 21) | std::uint64_t(k & 0x1FFFFF);
    };
    PointSet centres;
    for (const Hole& h : holes) {
        const double reach = 0.5 * h.radius;
        const std::int64_t span = std::int64_t(std::ceil(reach / cube));
        const std::int64_t ci = cell(h.centre[0]), cj = cell(h.centre[1]), ck = cell(h.centre[2]);
        bool seen = false;
        for (std::int64_t i = ci - span; i <= ci + span && !seen; ++i)
            for (std::int64_t j = cj - span; j <= cj + span && !seen; ++j)
                for (std::int64_t k = ck - span; k <= ck + span && !seen; ++k) {
                    const auto at = filed.find(key(i, j, k));
                    if (at == filed.end()) continue;
                    for (std::uint32_t c : at->second) seen = seen || norm(sub(centres[c], h.centre)) < reach;
                }
        if (seen) continue;
        filed[key(ci, cj, ck)].push_back(std::uint32_t(centres.size()));
        centres.push_back(h.centre);
    }
    return centres;
}

// The points of [begin, end) within `reach` of one of `near_points` (where the last pass
// changed the holes), ascending: found from them, a search about each (a later pass's few
// thousand centres), not one from each of the millions of points; a point's distance to a
// centre measured as a search from it measures it.
std::vector<std::uint32_t> points_near(const detail::PointTree& tree, const PointSet& near_points, double reach,
                                       std::size_t begin, std::size_t end) {
    const PointCloud near_cloud(near_points);
    const detail::PointTree& near = detail::tree_of(near_cloud);
    const double r_sq = reach * reach;
    std::vector<std::uint8_t> within(end - begin, 0);
    for (std::size_t c = 0; c < near.size(); ++c) {
        const Vec3 at = near.point(c);
        tree.for_each_within(at, std::nextafter(r_sq, std::numeric_limits<double>::infinity()), [&](std::uint32_t k) {
            if (k >= begin && k < end && detail::PointTree::dist_sq(tree.point(k), at) <= r_sq) within[k - begin] = 1;
        });
    }
    std::vector<std::uint32_t> look;
    for (std::size_t i = 0; i < within.size(); ++i)
        if (within[i]) look.push_back(std::uint32_t(begin + i));
    return look;
}

// The holes wider than `least` at the tree's points [begin, end), or at those `look` lists
// (ascending, among them) where given. Where told, in parts of a 32nd of the points
// looked at (at least kToldPart: a part takes 30-400 ms at 7.5-50 us a point, a barrier
// between them nothing), told between them.
constexpr std::size_t kToldPart = 4096;
std::vector<Hole> holes_at_points(const detail::PointTree& tree, double least, std::size_t begin, std::size_t end,
                                  const std::vector<std::uint32_t>* look, const HolesTold& told = nullptr,
                                  int pass = 1) {
    const std::size_t n = look ? look->size() : end - begin;
    std::vector<std::vector<Hole>> at(n);
    const std::size_t part = told ? std::max(kToldPart, n / 32) : std::max<std::size_t>(n, 1);
    if (told) told(0, n, pass);
    for (std::size_t from = 0; from < n; from += part) {
        const std::ptrdiff_t first = std::ptrdiff_t(from), last = std::ptrdiff_t(std::min(n, from + part));
#pragma omp parallel for schedule(dynamic, 64) if (last - first >= detail::kParallelCostlyItems)
        for (std::ptrdiff_t i = first; i < last; ++i) {
            const std::uint32_t k = look ? (*look)[std::size_t(i)] : std::uint32_t(begin + std::size_t(i));
            at[std::size_t(i)] = holes_at(tree, k, least, false);
        }
        if (told) told(std::size_t(last), n, pass);
    }
    std::vector<Hole> holes;
    for (const std::vector<Hole>& h : at) holes.insert(holes.end(), h.begin(), h.end());
    return holes;
}

// A pass's centres: at every point (with `near`, within `reach` of one of its points), the
// runs of other processes found there where asked.
PointSet centres_of_holes(const detail::PointTree& tree, double least, const PointSet& near, double reach,
                          const AskHoles& ask, const HolesTold& told, int pass) {
    std::vector<std::uint32_t> look;  // a later pass's points
    if (!near.empty()) look = points_near(tree, near, reach, 0, tree.size());
    const HolesElsewhere elsewhere = ask ? ask(tree, least, near, reach, near.empty() ? tree.size() : look.size())
                                         : HolesElsewhere{tree.size(), nullptr};
    look.erase(std::lower_bound(look.begin(), look.end(), std::uint32_t(elsewhere.here_end)), look.end());
    std::vector<Hole> holes =
        holes_at_points(tree, least, 0, elsewhere.here_end, near.empty() ? nullptr : &look, told, pass);
    if (elsewhere.collect) {
        const std::vector<double> theirs = elsewhere.collect();
        if (theirs.size() % 4) throw Error("the holes found by another process are not whole");
        for (std::size_t k = 0; k < theirs.size(); k += 4)
            holes.push_back({theirs[k], {theirs[k + 1], theirs[k + 2], theirs[k + 3]}});
    }
    return distinct_centres(std::move(holes), least);  // in an order of their own: none of the finding's
}

}  // namespace

double share_bordering_holes(const detail::PointTree& tree, double gap) {
    const std::vector<std::uint32_t> sample = detail::strided_sample(tree, HoleRules::samples);
    if (sample.empty()) return 0;
    const std::ptrdiff_t n = std::ptrdiff_t(sample.size());
    std::ptrdiff_t bordering = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : bordering) if (n >= detail::kParallelCostlyItems)
    for (std::ptrdiff_t s = 0; s < n; ++s) bordering += !holes_at(tree, sample[std::size_t(s)], gap, true).empty();
    return double(bordering) / double(n);
}

std::vector<double> holes_in_run(const detail::PointTree& tree, double least, std::size_t begin, std::size_t end,
                                 const PointSet& near, double reach) {
    std::vector<double> out;
    end = std::min(end, tree.size());
    std::vector<std::uint32_t> look;
    if (!near.empty()) look = points_near(tree, near, reach, begin, end);
    for (const Hole& h : holes_at_points(tree, least, begin, end, near.empty() ? nullptr : &look))
        out.insert(out.end(), {h.radius, h.centre[0], h.centre[1], h.centre[2]});
    return out;
}

PointSet hole_centres(const PointCloud& points, double least, const AskHoles& elsewhere, const HolesTold& told) {
    // A point at a wide hole's centre leaves narrower ones around it; a long hole may
    // need another: passes over the points and the centres so far, each looking only
    // near the last pass's centres (within the widest hole's reach: 3 least covers the
    // holes of random samplings, up to 2 least wide), until none is left.
    PointSet centres = centres_of_holes(detail::tree_of(points), least, {}, 0, elsewhere, told, 1);
    PointSet last = centres;
    for (int pass = 1; pass < HoleRules::passes && !last.empty(); ++pass) {
        const PointCloud with = detail::cloud_with(points, centres);
        last = centres_of_holes(detail::tree_of(with), least, last, 3 * least, elsewhere, told, pass + 1);
        centres.insert(centres.end(), last.begin(), last.end());
    }
    return centres;
}

}  // namespace snvr
