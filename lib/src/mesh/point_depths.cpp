// PointDepths (point_depths.hpp): a dense scan has a hundred points or more per voxel
// of surface, and a nearest-triangle search per point cost more than the whole
// reconstruction; a group of points shares its candidate triangles instead, and each
// leaf of it (about ten points) keeps those within its own reach.
#include "mesh/point_depths.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "geometry/vec3_math.hpp"

namespace snvr::detail {

// A triangle's frame, the same wherever its group lies: which corner is a (the start of
// its longest edge; the triangle turned, not mirrored), the unit vectors u (along ab), v
// (in its plane, towards c) and n, ab's length and its inverse, c in (u, v), and the
// inverse squared lengths of bc and ca (0 for none: a degenerate triangle is then its
// edges, an edge its corner). In float, as the lanes take them.
struct TriangleFrame {
    float values[15];  // ux uy uz vx vy vz nx ny nz len inv_len cx cy inv_bc inv_ca
    int first;         // the corner that is a
};

static TriangleFrame triangle_frame(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const Vec3 r[3] = {p0, p1, p2};
    const double e[3] = {norm(sub(r[1], r[0])), norm(sub(r[2], r[1])), norm(sub(r[0], r[2]))};
    TriangleFrame f{};
    f.first = e[0] >= e[1] && e[0] >= e[2] ? 0 : e[1] >= e[2] ? 1 : 2;
    const Vec3 a = r[f.first], b = r[(f.first + 1) % 3], c = r[(f.first + 2) % 3];
    const double length = e[f.first];
    const Vec3 u = length > 0 ? Vec3{(b[0] - a[0]) / length, (b[1] - a[1]) / length, (b[2] - a[2]) / length}
                              : Vec3{1, 0, 0};
    // The normal made square to u (a nearly flat triangle's cross product is mostly
    // rounding); a segment or a point gets any normal across u.
    Vec3 n = cross(sub(b, a), sub(c, a));
    const double along = dot(n, u);
    for (int d = 0; d < 3; ++d) n[d] -= along * u[d];
    double nn = norm(n);
    if (!(nn > 1e-9 * length * norm(sub(c, a)))) {
        n = std::fabs(u[0]) < 0.9 ? cross(u, Vec3{1, 0, 0}) : cross(u, Vec3{0, 1, 0});
        nn = norm(n);
    }
    for (double& x : n) x /= nn;
    const Vec3 v = cross(n, u);
    const Vec3 ac = sub(c, a);
    const double cu = dot(ac, u), cv = dot(ac, v);
    const auto inverse_sq = [](double x, double y) {
        const double s = x * x + y * y;
        return s > 0 && std::isfinite(1 / s) ? float(1 / s) : 0.0f;
    };
    const float values[15] = {float(u[0]), float(u[1]), float(u[2]), float(v[0]), float(v[1]), float(v[2]),
                              float(n[0]), float(n[1]), float(n[2]), float(length),
                              length > 0 ? float(1 / length) : 0.0f, float(cu), float(cv),
                              inverse_sq(cu - length, cv), inverse_sq(cu, cv)};
    std::copy(values, values + 15, f.values);
    return f;
}

namespace {

// Groups of at most this many points and this half diagonal (unless a leaf): a group
// shares the grid search, each of its leaves then a shorter list.
constexpr std::uint32_t kGroupPoints = 256;
constexpr double kGroupVoxels = 3;
// Below this many points in a group, each point searches the grid on its own (a sparse
// scan: the shared search would cost more than it saves).
constexpr std::uint32_t kFewPoints = 16;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr std::uint32_t kNone = std::uint32_t(-1);

// Triangles about a group's centre in float, each in a frame of its own: corner a, the
// unit vectors u (along its longest edge ab), v (in its plane, towards c) and n, the
// longest edge's length and c in (u, v), and the inverse squared lengths of bc and ca (0
// for none: a degenerate triangle is then its edges, an edge its corner). In packets of
// eight, a field's eight values side by side, so that the lanes load them at once and a
// triangle's fields lie close together.
struct LaneTriangles {
    enum Field { ax, ay, az, ux, uy, uz, vx, vy, vz, nx, ny, nz, len, inv_len, cx, cy, inv_bc, inv_ca, kFields };
    static constexpr std::size_t kPacket = 8 * kFields;
    std::vector<float> block;
    std::vector<std::uint32_t> id;  // the mesh's triangles, kNone for the padding (pad())
    std::size_t count = 0;          // triangles, the padding not counted
    double reach = 0;               // the largest distance of a corner from the centre

    std::size_t size() const { return count; }
    std::size_t packets() const { return (count + 7) / 8; }
    const float* packet(std::size_t p) const { return block.data() + p * kPacket; }
    float at(int field, std::size_t j) const { return block[j / 8 * kPacket + std::size_t(field) * 8 + j % 8]; }
    float& at(int field, std::size_t j) { return block[j / 8 * kPacket + std::size_t(field) * 8 + j % 8]; }

    // Room for n triangles and their padding (the block's contents are then undefined).
    void reset(std::size_t n) {
        id.clear();
        count = 0;
        reach = 0;
        const std::size_t need = (n + 7) / 8 * kPacket;
        if (block.size() < need) block.resize(std::max(need, 2 * block.size()));
    }
    void add(std::uint32_t t, const TriangleFrame& f, const Vec3& a) {
        const std::size_t j = count++;
        at(ax, j) = float(a[0]);
        at(ay, j) = float(a[1]);
        at(az, j) = float(a[2]);
        for (int k = ux; k < kFields; ++k) at(k, j) = f.values[k - ux];
        id.push_back(t);
    }
    // Keeps the triangles whose flag is set, in order.
    void keep(const std::vector<std::uint8_t>& flags) {
        std::size_t to = 0;
        for (std::size_t j = 0; j < count; ++j)
            if (flags[j]) {
                for (int k = 0; k < kFields; ++k) at(k, to) = at(k, j);
                id[to++] = id[j];
            }
        count = to;
        id.resize(to);
        pad();
    }
    // The triangles of `from` whose flag is set, in order.
    void take(const LaneTriangles& from, const std::vector<std::uint8_t>& flags) {
        std::size_t n = 0;
        for (std::size_t j = 0; j < from.size(); ++j) n += flags[j];
        reset(n);
        reach = from.reach;
        for (std::size_t j = 0; j < from.size(); ++j)
            if (flags[j]) {
                for (int k = 0; k < kFields; ++k) at(k, count) = from.at(k, j);
                id.push_back(from.id[j]);
                ++count;
            }
        pad();
    }
    // Fills the last packet with points far beyond any other (at 1e18 on each axis, the
    // axes as frame: a squared distance near 3e36, still finite), whose id is kNone.
    void pad() {
        const std::size_t padded = packets() * 8;
        for (std::size_t j = count; j < padded; ++j)
            for (int k = 0; k < kFields; ++k) at(k, j) = k < 3 ? 1e18f : k == ux || k == vy || k == nz ? 1.0f : 0.0f;
        id.resize(padded, kNone);
    }
};

// Eight floats in vector lanes (GCC's vector extensions; AVX2 registers where the
// machine has them, pairs of SSE ones else).
typedef float F8 __attribute__((vector_size(32)));
typedef std::int32_t I8 __attribute__((vector_size(32)));

// Squared distance from (x, y, z) to a triangle, in float, branch-free (selects, and `&`
// rather than `&&`), for one triangle (T = float) or eight (T = F8): in the triangle's
// frame, its plane's distance squared, plus, unless the point's foot lies inside the
// face, the squared distance in the plane to the nearest edge. get(field) gives the
// triangle's (or the eight's) value of a field.
template <class T, class Get>
__attribute__((always_inline)) inline T lane_dist_sq(T x, T y, T z, const Get& get) {
    using L = LaneTriangles;
    const T zero{}, one = zero + 1;
    const auto lower = [](T a, T b) { return a < b ? a : b; };
    const auto clamp01 = [&](T t) { return t < zero ? zero : (t > one ? one : t); };
    const T qx = x - get(L::ax), qy = y - get(L::ay), qz = z - get(L::az);
    const T pu = qx * get(L::ux) + qy * get(L::uy) + qz * get(L::uz);
    const T pv = qx * get(L::vx) + qy * get(L::vy) + qz * get(L::vz);
    const T pn = qx * get(L::nx) + qy * get(L::ny) + qz * get(L::nz);
    const T length = get(L::len), cu = get(L::cx), cv = get(L::cy);
    // Edge ab along u, from 0 to length.
    const T ta = clamp01(pu * get(L::inv_len));
    const T au = pu - ta * length;
    const T ab = au * au + pv * pv;
    // Edge bc, from (length, 0) to (cu, cv).
    const T bu = pu - length, eu = cu - length;
    const T tb = clamp01((bu * eu + pv * cv) * get(L::inv_bc));
    const T bu2 = bu - tb * eu, bv2 = pv - tb * cv;
    const T bc = bu2 * bu2 + bv2 * bv2;
    // Edge ca, from (cu, cv) to 0.
    const T wu = pu - cu, wv = pv - cv;
    const T tc = clamp01(-(wu * cu + wv * cv) * get(L::inv_ca));
    const T cu2 = wu + tc * cu, cv2 = wv + tc * cv;
    const T ca = cu2 * cu2 + cv2 * cv2;
    const auto inside = (cv > zero) & (pv >= zero) & (eu * pv - cv * bu >= zero) & (cv * pu - cu * pv >= zero);
    return pn * pn + (inside ? zero : lower(lower(ab, bc), ca));
}

// A point's three least squared distances over triangles, and the triangles of the two
// least (kNone where there are fewer).
struct Least {
    float d[3];
    std::uint32_t id[2];
};

// Least over the triangles, a packet at a time.
__attribute__((target_clones("avx2", "default"))) Least nearest_over_triangles(const LaneTriangles& t, float x,
                                                                             float y, float z) {
    const F8 inf = F8{} + std::numeric_limits<float>::infinity();
    const F8 px = F8{} + x, py = F8{} + y, pz = F8{} + z;
    F8 b1 = inf, b2 = inf, b3 = inf;
    I8 a1 = I8{} - 1, a2 = I8{} - 1;
    for (std::size_t p = 0; p < t.packets(); ++p) {
        const float* fields = t.packet(p);
        const auto get = [&](int field) {
            F8 v;
            std::memcpy(&v, fields + 8 * field, sizeof v);
            return v;
        };
        const F8 d = lane_dist_sq(px, py, pz, get);
        I8 id;
        std::memcpy(&id, t.id.data() + 8 * p, sizeof id);
        const I8 n1 = d < b1, n2 = d < b2, n3 = d < b3;
        b3 = n2 ? b2 : (n3 ? d : b3);
        b2 = n1 ? b1 : (n2 ? d : b2);
        a2 = n1 ? a1 : (n2 ? id : a2);
        b1 = n1 ? d : b1;
        a1 = n1 ? id : a1;
    }
    // Each lane holds its three least in order: the overall least is the least head, and
    // each next one the least head of what is left.
    int l1 = 0;
    for (int l = 1; l < 8; ++l)
        if (b1[l] < b1[l1]) l1 = l;
    Least least{{b1[l1], b2[l1], b3[l1]}, {std::uint32_t(a1[l1]), std::uint32_t(a2[l1])}};
    int l2 = -1;  // the lane of the second, when not l1's own second
    for (int l = 0; l < 8; ++l)
        if (l != l1 && b1[l] < least.d[1]) {
            least.d[1] = b1[l];
            least.id[1] = std::uint32_t(a1[l]);
            l2 = l;
        }
    least.d[2] = l2 < 0 ? b3[l1] : std::min(b2[l1], b2[l2]);
    for (int l = 0; l < 8; ++l)
        if (l != l1 && l != l2) least.d[2] = std::min(least.d[2], b1[l]);
    return least;
}

// The squared distance from one point to each triangle (and the padding), a packet at a time.
__attribute__((target_clones("avx2", "default"))) void distances_over_triangles(const LaneTriangles& t, float x,
                                                                              float y, float z, float* out) {
    const F8 px = F8{} + x, py = F8{} + y, pz = F8{} + z;
    for (std::size_t p = 0; p < t.packets(); ++p) {
        const float* fields = t.packet(p);
        const F8 d = lane_dist_sq(px, py, pz, [&](int field) {
            F8 v;
            std::memcpy(&v, fields + 8 * field, sizeof v);
            return v;
        });
        std::memcpy(out + 8 * p, &d, sizeof d);
    }
}

// A call's working space, kept from group to group.
struct Scratch {
    std::vector<std::uint32_t> near, seen;
    std::uint32_t mark = 0;
    LaneTriangles group, leaf;
    std::vector<float> from, x, y, z;
    std::vector<std::uint8_t> flags;
    std::vector<std::uint32_t> nearest;
    std::vector<double> d2;
};

}  // namespace

PointDepths::~PointDepths() = default;

PointDepths::PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel)
    : mesh_(mesh), grid_(grid), points_(points) {
    const double most = kGroupVoxels * voxel;
    points.for_each_leaf(
        [&](const PointTree::Node& n) {
            if (n.leaf()) return true;
            const double half_diag = 0.5 * std::sqrt(PointTree::dist_sq(points.lo(n), points.hi(n)));
            if (n.count() <= kGroupPoints && half_diag <= most) {
                groups_.push_back(&n);  // a group of its own: nothing below is entered
                return false;
            }
            return true;
        },
        [&](const PointTree::Node& n) { groups_.push_back(&n); });
    frames_.resize(mesh.triangles.size());
    const std::ptrdiff_t nt = std::ptrdiff_t(mesh.triangles.size());
#pragma omp parallel for schedule(static) if (nt > (1 << 14))
    for (std::ptrdiff_t t = 0; t < nt; ++t) {
        const auto& tri = mesh.triangles[t];
        frames_[t] = triangle_frame(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    }
    if (!mesh.vertices.empty()) {
        lo_ = hi_ = mesh.vertices[0];
        for (const Vec3& v : mesh.vertices)
            for (int d = 0; d < 3; ++d) {
                lo_[d] = std::min(lo_[d], v[d]);
                hi_[d] = std::max(hi_[d], v[d]);
            }
    }
}

void PointDepths::measure(std::size_t first, std::size_t last, bool by_rays, std::vector<double>& depth) const {
    Scratch s;
    double before = kInf;  // the last group's centre's distance to the surface
    Vec3 before_at{0, 0, 0};
    for (std::size_t g = first; g < last; ++g) {
        const PointTree::Node& node = *groups_[g];
        const Vec3 lo = points_.lo(node), hi = points_.hi(node);
        const Vec3 centre{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
        // Within the last group's distance plus the way between them: a tight bound.
        const double guess = before + norm(sub(centre, before_at));
        TriangleGrid::Closest at = grid_.closest(centre, guess * guess * (1 + 1e-9));
        if (at.triangle == TriangleGrid::none) at = grid_.closest(centre);
        before = std::sqrt(at.dist_sq);
        before_at = centre;
        measure_group(node, centre, at.dist_sq, by_rays, &s, depth);
    }
}

void PointDepths::measure_group(const PointTree::Node& node, const Vec3& centre, double centre_sq, bool by_rays,
                                void* scratch, std::vector<double>& depth) const {
    Scratch& s = *static_cast<Scratch*>(scratch);
    const std::uint32_t count = node.count();
    double radius = 0;
    for (std::uint32_t k = node.begin; k < node.end; ++k)
        radius = std::max(radius, PointTree::dist_sq(points_.point(k), centre));
    radius = std::sqrt(radius);
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    s.d2.assign(count, kInf);
    s.nearest.assign(count, kNone);

    if (centre_sq < kInf && count < kFewPoints) {
        // Too few to share a search: each point's own, bounded by the centre's distance
        // plus the way to it.
        for (std::uint32_t k = 0; k < count; ++k) {
            const Vec3 p = points_.point(node.begin + k);
            const double bound = std::sqrt(centre_sq) + norm(sub(p, centre));
            TriangleGrid::Closest near = grid_.closest(p, bound * bound * (1 + 1e-9) + 1e-300);
            if (near.triangle == TriangleGrid::none) near = grid_.closest(p);
            s.d2[k] = near.dist_sq;
            s.nearest[k] = near.triangle == TriangleGrid::none ? kNone : near.triangle;
        }
    } else if (centre_sq < kInf) {
        // Each point's nearest triangle lies within d + r of it, d the centre's distance
        // to the surface: within d + 2 r of the centre. The grid's boxes give a superset, a
        // ball around each triangle (centroid, farthest corner) a smaller one, and the
        // triangles' own distances to the centre (in float, with room for its rounding)
        // keep those that can matter.
        const double reach = (std::sqrt(centre_sq) + 2 * radius) * (1 + 1e-9) + 1e-12 * (radius + 1);
        if (s.seen.size() != T.size()) s.seen.assign(T.size(), 0);
        grid_.near(centre, reach, s.near, s.seen, ++s.mark);
        LaneTriangles& group = s.group;
        group.reset(s.near.size());
        for (std::uint32_t t : s.near) {
            const Vec3 &a = V[T[t][0]], &b = V[T[t][1]], &c = V[T[t][2]];
            const Vec3 mid{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
            const double ball = std::max({norm(sub(a, mid)), norm(sub(b, mid)), norm(sub(c, mid))});
            if (norm(sub(centre, mid)) - ball > reach * (1 + 1e-9)) continue;
            const TriangleFrame& f = frames_[t];
            const Vec3 corner = sub(V[T[t][std::size_t(f.first)]], centre);
            group.reach = std::max({group.reach, norm(sub(a, centre)), norm(sub(b, centre)), norm(sub(c, centre))});
            group.add(t, f, corner);
        }
        group.pad();
        // The floats err by far less than this: every value below (2 R)^2, R the largest
        // coordinate about the centre, and rounded a dozen times by 2^-24 of it.
        const double big = 2 * std::max(group.reach, radius);
        const double slack = 0x1p-18 * big * big;
        s.from.resize(group.packets() * 8);
        distances_over_triangles(group, 0, 0, 0, s.from.data());
        s.flags.resize(group.size());
        for (std::size_t j = 0; j < group.size(); ++j) s.flags[j] = double(s.from[j]) <= reach * reach + slack;
        group.keep(s.flags);

        for (auto* v : {&s.x, &s.y, &s.z}) v->resize(count);
        for (std::uint32_t k = 0; k < count; ++k) {
            const Vec3 p = sub(points_.point(node.begin + k), centre);
            s.x[k] = float(p[0]);
            s.y[k] = float(p[1]);
            s.z[k] = float(p[2]);
        }
        const auto exact = [&](const Vec3& p, std::uint32_t t, std::uint32_t k) {
            const double e = point_triangle_dist_sq(p, V[T[t][0]], V[T[t][1]], V[T[t][2]]);
            if (e < s.d2[k] || (e == s.d2[k] && t < s.nearest[k])) s.d2[k] = e, s.nearest[k] = t;
        };
        // Then each leaf the same way, about its point nearest its box's centre: the
        // group's triangles within d + 2 r of that point, r the leaf's radius about it.
        points_.for_each_leaf_below(
            node, [](const PointTree::Node&) { return true; },
            [&](const PointTree::Node& leaf) {
                const Vec3 llo = points_.lo(leaf), lhi = points_.hi(leaf);
                const Vec3 middle{0.5 * (llo[0] + lhi[0]), 0.5 * (llo[1] + lhi[1]), 0.5 * (llo[2] + lhi[2])};
                std::uint32_t ref = leaf.begin;
                for (std::uint32_t k = leaf.begin + 1; k < leaf.end; ++k)
                    if (PointTree::dist_sq(points_.point(k), middle) < PointTree::dist_sq(points_.point(ref), middle))
                        ref = k;
                const Vec3 at = points_.point(ref);
                double leaf_radius = 0;
                for (std::uint32_t k = leaf.begin; k < leaf.end; ++k)
                    leaf_radius = std::max(leaf_radius, PointTree::dist_sq(points_.point(k), at));
                leaf_radius = std::sqrt(leaf_radius);
                const std::uint32_t r = ref - node.begin;
                distances_over_triangles(group, s.x[r], s.y[r], s.z[r], s.from.data());
                float least = kInfF;
                for (std::size_t j = 0; j < group.size(); ++j) least = std::min(least, s.from[j]);
                const double leaf_reach = (std::sqrt(double(least) + slack) + 2 * leaf_radius) * (1 + 1e-9);
                for (std::size_t j = 0; j < group.size(); ++j)
                    s.flags[j] = double(s.from[j]) <= leaf_reach * leaf_reach + slack;
                LaneTriangles& mine = s.leaf;
                mine.take(group, s.flags);
                // A least value clear of the next by twice the slack is the exact least: only
                // its triangle is measured in double; two near-equal ones (a foot near the edge
                // they share) both; more, every triangle of the leaf.
                for (std::uint32_t k = leaf.begin - node.begin; k < leaf.end - node.begin; ++k) {
                    const Least low = nearest_over_triangles(mine, s.x[k], s.y[k], s.z[k]);
                    if (low.id[0] == kNone) continue;
                    const Vec3 p = points_.point(node.begin + k);
                    if (double(low.d[1]) - double(low.d[0]) > 2 * slack) {
                        exact(p, low.id[0], k);
                    } else if (double(low.d[2]) - double(low.d[0]) > 2 * slack) {
                        exact(p, low.id[0], k);
                        exact(p, low.id[1], k);
                    } else {
                        for (std::size_t j = 0; j < mine.size(); ++j) exact(p, mine.id[j], k);
                    }
                }
            });
    }

    // Inside or not by the parity of crossings along a ray in a direction that no
    // grid-aligned edge of a marching-cubes mesh is parallel to, heading for the nearer
    // face of the mesh's box on every axis to cut the walk short.
    const Vec3 dir = [] {
        const Vec3 d{0.5377, 0.3019, 0.7877};
        const double n = norm(d);
        return Vec3{d[0] / n, d[1] / n, d[2] / n};
    }();
    for (std::uint32_t k = 0; k < count; ++k) {
        const Vec3 p = points_.point(node.begin + k);
        const double d = std::sqrt(s.d2[k]);
        int side = 0;
        if (!by_rays && s.nearest[k] != kNone) {
            const auto& t = T[s.nearest[k]];
            side = face_side(p, V[t[0]], V[t[1]], V[t[2]]);
        }
        if (side == 0) {
            Vec3 toward = dir;
            for (int a = 0; a < 3; ++a)
                if (p[a] - lo_[a] < hi_[a] - p[a]) toward[a] = -toward[a];
            side = grid_.count_crossings(p, toward) % 2 == 1 ? -1 : 1;
        }
        depth[node.begin + k] = side < 0 ? d : -d;
    }
}

}  // namespace snvr::detail
