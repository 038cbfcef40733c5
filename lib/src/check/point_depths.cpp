// PointDepths (point_depths.hpp): a dense scan has a hundred points or more per voxel
// of surface, and a nearest-triangle search per point cost more than the whole
// reconstruction. A group of points shares one search and its list of candidate
// triangles; a lower bound for the whole group settles most groups without a look at
// their single points.
#include "check/point_depths.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>

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
    double radius;     // the farthest corner from a
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
    f.radius = std::max(length, norm(ac));
    return f;
}

namespace {

Vec3 mid(const Vec3& a, const Vec3& b) { return {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])}; }

// Groups of at most this many points and this half diagonal (unless a single leaf): a
// group shares one grid search and its list of triangles, and the larger, the longer the
// list and the looser its bound.
constexpr std::uint32_t kGroupPoints = 256;
constexpr double kGroupVoxels = 0.75;
// Up to this many points every depth is measured, for the percentile; beyond, the groups
// of about kSamplePoints points, evenly spread (the least depth is always exact).
constexpr std::size_t kExactPoints = std::size_t(1) << 18;
constexpr std::size_t kSamplePoints = std::size_t(1) << 18;
// Below this many points in a run, each point searches the grid on its own (a sparse
// scan: the shared search would cost more than it saves).
constexpr std::uint32_t kFewPoints = 16;
// A group farther than this from the last starts its search afresh (its bound would let
// too many triangles through).
constexpr double kJumpVoxels = 8;
// Neighbouring groups share one grid search: a run of consecutive groups whose box has
// at most this half diagonal (and at most kRunGroups of them) takes the triangles within
// reach of all of them at once, and each group then keeps its own from that list (in the
// lanes, far cheaper than a search). Wider runs pass longer lists to each group.
constexpr double kRunVoxels = 1.5;
constexpr std::size_t kRunGroups = 32;
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

// A packet's fields in lanes, as lane_offset's get() takes them.
struct PacketFields {
    const float* fields;
    __attribute__((always_inline)) F8 operator()(int field) const {
        F8 v;
        std::memcpy(&v, fields + 8 * field, sizeof v);
        return v;
    }
};

// The offset from a triangle's nearest point to (x, y, z), in the triangle's frame (du
// along u, dv along v, dn along n), in float, branch-free (selects, and `&` rather than
// `&&`), for one triangle (T = float) or eight (T = F8): in its plane, none where the
// point's foot lies inside the face, else to the nearest edge. get(field) gives the
// triangle's (or the eight's) value of a field.
template <class T, class Get>
__attribute__((always_inline)) inline void lane_offset(T x, T y, T z, const Get& get, T& du, T& dv, T& dn) {
    using L = LaneTriangles;
    const T zero{}, one = zero + 1;
    const auto clamp01 = [&](T t) { return t < zero ? zero : (t > one ? one : t); };
    const T qx = x - get(L::ax), qy = y - get(L::ay), qz = z - get(L::az);
    const T pu = qx * get(L::ux) + qy * get(L::uy) + qz * get(L::uz);
    const T pv = qx * get(L::vx) + qy * get(L::vy) + qz * get(L::vz);
    dn = qx * get(L::nx) + qy * get(L::ny) + qz * get(L::nz);
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
    const auto to_ab = (ab <= bc) & (ab <= ca), to_bc = bc <= ca;
    du = inside ? zero : (to_ab ? au : (to_bc ? bu2 : cu2));
    dv = inside ? zero : (to_ab ? pv : (to_bc ? bv2 : cv2));
}

// The squared distance from (x, y, z) to a triangle (or eight), as lane_offset.
template <class T, class Get>
__attribute__((always_inline)) inline T lane_dist_sq(T x, T y, T z, const Get& get) {
    T du, dv, dn;
    lane_offset(x, y, z, get, du, dv, dn);
    return du * du + dv * dv + dn * dn;
}

// A point's three least squared distances over triangles, and the triangles of the two
// least (kNone where there are fewer).
struct Least {
    float d[3];
    std::uint32_t id[2];
};

// Lower bounds of each triangle's distance near a reference point r, in packets of eight
// like the triangles': its distance D from r and the unit gradient g of that distance
// there. A triangle is convex, so its distance is a convex function of the point and
// lies above its tangent plane: dist(p) >= D + g . (p - r).
struct TangentBounds {
    std::vector<float> v;  // per packet: D[8], gx[8], gy[8], gz[8]
    static constexpr std::size_t kPacket = 32;
};

// Packet p's tangent bounds in lanes: D, and g's three components.
struct TangentLanes {
    F8 d, gx, gy, gz;
};
__attribute__((always_inline)) inline TangentLanes tangent_lanes(const float* bounds, std::size_t p) {
    const float* b = bounds + p * TangentBounds::kPacket;
    TangentLanes t;
    std::memcpy(&t.d, b, sizeof t.d);
    std::memcpy(&t.gx, b + 8, sizeof t.gx);
    std::memcpy(&t.gy, b + 16, sizeof t.gy);
    std::memcpy(&t.gz, b + 24, sizeof t.gz);
    return t;
}

// Returns the first of the nearest triangles (by D; the padding is never nearer).
__attribute__((target_clones("avx2", "default"))) std::size_t tangents_over_triangles(const LaneTriangles& t,
                                                                                    float x, float y, float z,
                                                                                    float* out) {
    const F8 px = F8{} + x, py = F8{} + y, pz = F8{} + z;
    F8 least = F8{} + std::numeric_limits<float>::infinity();
    I8 first = I8{};  // the packet of each lane's least, the first where they tie
    for (std::size_t p = 0; p < t.packets(); ++p) {
        const PacketFields get{t.packet(p)};
        F8 du, dv, dn;
        lane_offset(px, py, pz, get, du, dv, dn);
        const F8 d2 = du * du + dv * dv + dn * dn;
        F8 d;
        for (int l = 0; l < 8; ++l) d[l] = std::sqrt(d2[l]);
        const F8 zero{};
        const F8 inv = d > zero ? (zero + 1) / d : zero;  // no direction at distance 0: no bound but D
        using L = LaneTriangles;
        const F8 gx = (du * get(L::ux) + dv * get(L::vx) + dn * get(L::nx)) * inv;
        const F8 gy = (du * get(L::uy) + dv * get(L::vy) + dn * get(L::ny)) * inv;
        const F8 gz = (du * get(L::uz) + dv * get(L::vz) + dn * get(L::nz)) * inv;
        float* to = out + p * TangentBounds::kPacket;
        std::memcpy(to, &d, sizeof d);
        std::memcpy(to + 8, &gx, sizeof gx);
        std::memcpy(to + 16, &gy, sizeof gy);
        std::memcpy(to + 24, &gz, sizeof gz);
        const I8 nearer = d < least;
        least = nearer ? d : least;
        first = nearer ? I8{} + std::int32_t(p) : first;
    }
    std::size_t best = std::size_t(first[0]) * 8;
    for (std::size_t l = 1; l < 8; ++l) {
        const std::size_t j = std::size_t(first[l]) * 8 + l, b = best;
        if (least[l] < least[b % 8] || (least[l] == least[b % 8] && j < b)) best = j;
    }
    return best;
}

// The least tangent bound, at the offset (x, y, z) from the reference point, of the
// triangles in the given packets: a lower bound of their distance there.
__attribute__((target_clones("avx2", "default"))) float least_tangent_bound(const float* bounds,
                                                                          const std::vector<std::uint32_t>& packets,
                                                                          float x, float y, float z) {
    F8 least = F8{} + std::numeric_limits<float>::infinity();
    for (std::uint32_t p : packets) {
        const TangentLanes g = tangent_lanes(bounds, p);
        const F8 low = g.d + g.gx * x + g.gy * y + g.gz * z;
        least = low < least ? low : least;
    }
    float m = least[0];
    for (int l = 1; l < 8; ++l) m = std::min(m, least[l]);
    return m;
}

// The least over the triangles of D + min(c lo, c hi) - sqrt(1 - c^2) across, c = g . n:
// a lower bound of every distance at points whose offset from the reference point lies
// between lo and hi along the unit n and within `across` of that line.
__attribute__((target_clones("avx2", "default"))) float least_group_bound(const LaneTriangles& t, const float* bounds,
                                                                        float nx, float ny, float nz, float lo,
                                                                        float hi, float across) {
    const F8 zero{}, one = zero + 1;
    F8 least = zero + std::numeric_limits<float>::infinity();
    for (std::size_t p = 0; p < t.packets(); ++p) {
        const TangentLanes g = tangent_lanes(bounds, p);
        const F8 c = g.gx * nx + g.gy * ny + g.gz * nz;
        F8 s2 = one - c * c;
        s2 = s2 > zero ? s2 : zero;
        F8 sine;
        for (int l = 0; l < 8; ++l) sine[l] = std::sqrt(s2[l]);
        const F8 a = c * lo, z = c * hi;
        const F8 v = g.d + (a < z ? a : z) - sine * across;
        least = v < least ? v : least;
    }
    float m = least[0];
    for (int l = 1; l < 8; ++l) m = std::min(m, least[l]);
    return m;
}

// Least over the triangles, a packet at a time; a packet whose every tangent bound
// (about the reference point (rx, ry, rz)) lies beyond the best distance so far (at
// first `start`, at least the point's distance) by `margin` (far above their rounding)
// cannot come near the least: it is passed by.
__attribute__((target_clones("avx2", "default"))) Least nearest_over_triangles(const LaneTriangles& t,
                                                                             const float* bounds, float x, float y,
                                                                             float z, float rx, float ry, float rz,
                                                                             float start, float margin) {
    const F8 inf = F8{} + std::numeric_limits<float>::infinity();
    const F8 px = F8{} + x, py = F8{} + y, pz = F8{} + z;
    const F8 ox = F8{} + (x - rx), oy = F8{} + (y - ry), oz = F8{} + (z - rz);
    F8 b1 = inf, b2 = inf, b3 = inf;
    I8 a1 = I8{} - 1, a2 = I8{} - 1;
    float best = start;  // the least distance so far
    for (std::size_t p = 0; p < t.packets(); ++p) {
        {
            const TangentLanes g = tangent_lanes(bounds, p);
            const F8 low = g.d + g.gx * ox + g.gy * oy + g.gz * oz;
            float least_low = low[0];
            for (int l = 1; l < 8; ++l) least_low = std::min(least_low, low[l]);
            if (least_low >= best + margin) continue;
        }
        const PacketFields get{t.packet(p)};
        const F8 d = lane_dist_sq(px, py, pz, get);
        I8 id;
        std::memcpy(&id, t.id.data() + 8 * p, sizeof id);
        const I8 n1 = d < b1, n2 = d < b2, n3 = d < b3;
        b3 = n2 ? b2 : (n3 ? d : b3);
        b2 = n1 ? b1 : (n2 ? d : b2);
        a2 = n1 ? a1 : (n2 ? id : a2);
        b1 = n1 ? d : b1;
        a1 = n1 ? id : a1;
        float least = b1[0];
        for (int l = 1; l < 8; ++l) least = std::min(least, b1[l]);
        best = std::min(best, std::sqrt(least));
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

// The least float squared distance from (x, y, z) to the triangles, as lane_dist_sq.
__attribute__((target_clones("avx2", "default"))) float least_over_triangles(const LaneTriangles& t, float x,
                                                                           float y, float z) {
    const F8 px = F8{} + x, py = F8{} + y, pz = F8{} + z;
    F8 least = F8{} + std::numeric_limits<float>::infinity();
    for (std::size_t p = 0; p < t.packets(); ++p) {
        const PacketFields get{t.packet(p)};
        const F8 d = lane_dist_sq(px, py, pz, get);
        least = d < least ? d : least;
    }
    float m = least[0];
    for (int l = 1; l < 8; ++l) m = std::min(m, least[l]);
    return m;
}

// The frames of the triangles a pass's runs gathered lately, in slots by a hash of each's
// block of 16 consecutive triangles (neighbours in the mesh's order stay side by side, as
// in a table of all): the next run, beside the last, finds most of its own there (the
// 50 M-point city block at 1024: 147 M frames taken, 9.9 M made, for 8.8 M triangles;
// hashed one by one, the lookups cost what the whole mesh's table's faults had saved).
// A frame a triangle of the whole mesh, made on first use, was 72 bytes a triangle at the
// check's peak (2.3 GB at 32 M triangles) and a fresh page's fault each 57 of them.
class FrameCache {
public:
    const TriangleFrame& of(std::uint32_t t, const Mesh& mesh) {
        if (slots_.empty()) slots_.resize(kSlots);
        const std::size_t block = (std::uint64_t(t / kBlock) * 0x9E3779B97F4A7C15ull) >> (64 - kSlotBits + kBlockBits);
        Slot& slot = slots_[block * kBlock + t % kBlock];
        if (slot.triangle != t) {
            const auto& tri = mesh.triangles[t];
            slot.frame = triangle_frame(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
            slot.triangle = t;
        }
        return slot.frame;
    }

private:
    static constexpr int kSlotBits = 16, kBlockBits = 4;  // 64 K frames, 5 MB: a run gathers a few hundred
    static constexpr std::size_t kSlots = std::size_t(1) << kSlotBits, kBlock = std::size_t(1) << kBlockBits;
    struct Slot {
        TriangleFrame frame;
        std::uint32_t triangle = kNone;
    };
    std::vector<Slot> slots_;
};

}  // namespace

// A group's working space, kept from group to group (and its arrays from pass to pass:
// PointDepths::scratches_).
struct DepthScratch {
    std::vector<std::uint32_t> near;
    std::vector<std::uint64_t> seen;  // TriangleGrid::near's
    FrameCache frames;
    // The run's candidates about its centre.
    LaneTriangles kept;
    Vec3 run_centre{0, 0, 0};
    double run_reach = 0;     // every triangle within this of run_centre is in `kept`
    double run_distance = 0;  // run_centre's distance to the surface, at most
    TangentBounds tangents;   // the kept's, about the group's centre
    std::vector<std::uint32_t> packets;
    double shallowest = kInf;  // the least depth this pass has measured inside
    bool run_unsure = false;   // a part's run reached beyond its triangles
    bool unsure = false;       // the group being visited cannot be decided here
    // As made, its arrays' room kept.
    void start_pass() {
        kept.reset(0);
        run_centre = {0, 0, 0};
        run_reach = run_distance = 0;
        shallowest = kInf;
        run_unsure = unsure = false;
    }
};

namespace {

// Inside or not by the parity of crossings along ray_toward's ray. -1 inside, +1 outside.
int ray_side(const TriangleGrid& grid, const Vec3& p, const Vec3& lo, const Vec3& hi) {
    return grid.count_crossings(p, PointDepths::ray_toward(p, lo, hi)) % 2 == 1 ? -1 : 1;
}

}  // namespace

PointDepths::~PointDepths() = default;

std::vector<PointDepths::Span> PointDepths::group_spans(const PointTree& points, double voxel, bool every_point) {
    // Leaves taken in Morton order, as many as fit in a group: neighbours in that order
    // lie side by side.
    const double most = kGroupVoxels * voxel;
    // At most a group per leaf, room made once: grown by doubling, a dense scan's million
    // groups were copied and their fresh pages faulted in several times over.
    std::size_t leaves = 0;
    points.for_each_leaf([](const PointTree::Node&) { return true; }, [&](const PointTree::Node&) { ++leaves; });
    std::vector<Span> spans;
    spans.reserve(leaves);
    Span open{};
    points.for_each_leaf([](const PointTree::Node&) { return true; }, [&](const PointTree::Node& leaf) {
        const Vec3 lo = points.lo(leaf), hi = points.hi(leaf);
        Span grown = open;
        for (int a = 0; a < 3; ++a) {
            grown.lo[a] = std::min(open.lo[a], lo[a]);
            grown.hi[a] = std::max(open.hi[a], hi[a]);
        }
        grown.end = leaf.end;
        const bool fits = leaf.end - open.begin <= kGroupPoints &&
                          0.5 * std::sqrt(PointTree::dist_sq(grown.lo, grown.hi)) <= most;
        if (open.end > open.begin && fits) {
            open = grown;
            return;
        }
        if (open.end > open.begin) spans.push_back(open);
        open = Span{};
        open.begin = leaf.begin;
        open.end = leaf.end;
        open.lo = lo;
        open.hi = hi;
    });
    if (open.end > open.begin) spans.push_back(open);
    // The groups the percentile is taken over: all of them for up to kExactPoints points,
    // else every stride-th (evenly over the Morton order: over the whole surface).
    const std::size_t n = points.size();
    const std::size_t stride = every_point || n <= kExactPoints ? 1 : (n + kSamplePoints - 1) / kSamplePoints;
    for (std::size_t g = 0; g < spans.size(); g += stride) spans[g].sampled = true;
    return spans;
}

PointDepths::Span PointDepths::span_of(const PointTree& points, std::uint32_t begin, std::uint32_t end) {
    if (!(begin < end && end <= points.size())) throw std::logic_error("PointDepths: a group beyond the points");
    Span s;
    s.begin = begin;
    s.end = end;
    s.lo = s.hi = points.point(begin);
    for (std::uint32_t k = begin + 1; k < end; ++k) {
        const Vec3 p = points.point(k);
        for (int a = 0; a < 3; ++a) {
            s.lo[a] = std::min(s.lo[a], p[a]);
            s.hi[a] = std::max(s.hi[a], p[a]);
        }
    }
    return s;
}

std::vector<PointDepths::Span> PointDepths::narrowed(const PointTree& points, double voxel, double widest,
                                                     std::vector<Span> spans) {
    const auto half_diagonal = [](const Vec3& lo, const Vec3& hi) { return 0.5 * std::sqrt(PointTree::dist_sq(lo, hi)); };
    const auto wide = [&](const Span& s) { return !s.sampled && half_diagonal(s.lo, s.hi) > widest; };
    if (std::none_of(spans.begin(), spans.end(), wide)) return spans;
    const double most = kGroupVoxels * voxel;
    std::vector<Span> out;
    out.reserve(spans.size());
    for (const Span& s : spans) {
        if (!wide(s)) {
            out.push_back(s);
            continue;
        }
        // Consecutive points while their box stays narrow: in the tree's (Morton) order a
        // line's points come mostly along it.
        Span piece = span_of(points, s.begin, s.begin + 1);
        for (std::uint32_t k = s.begin + 1; k < s.end; ++k) {
            const Vec3 p = points.point(k);
            Vec3 lo = piece.lo, hi = piece.hi;
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p[a]);
                hi[a] = std::max(hi[a], p[a]);
            }
            if (k - piece.begin < kGroupPoints && half_diagonal(lo, hi) <= most) {
                piece.lo = lo;
                piece.hi = hi;
                piece.end = k + 1;
                continue;
            }
            out.push_back(piece);
            piece = span_of(points, k, k + 1);
        }
        out.push_back(piece);
    }
    return out;
}

namespace {
std::vector<PointDepths::Span> spans_of(const PointTree& points, const std::vector<std::array<std::uint32_t, 2>>& runs) {
    std::vector<PointDepths::Span> spans(runs.size());
    for (std::size_t g = 0; g < runs.size(); ++g) spans[g] = PointDepths::span_of(points, runs[g][0], runs[g][1]);
    return spans;
}
}  // namespace

PointDepths::PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel,
                         bool every_point, bool by_rays, const std::vector<std::uint8_t>* skip, const Part* part)
    : PointDepths(mesh, grid, points, voxel, group_spans(points, voxel, every_point), every_point, by_rays, skip, part) {}

PointDepths::PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel,
                         const std::vector<std::array<std::uint32_t, 2>>& groups, const Part& part)
    : PointDepths(mesh, grid, points, voxel, spans_of(points, groups), false, false, nullptr, &part) {}

PointDepths::PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel,
                         const std::vector<Span>& spans, bool every_point, bool by_rays,
                         const std::vector<std::uint8_t>* skip, const Part* part)
    : mesh_(mesh), grid_(grid), points_(points), every_point_(every_point), by_rays_(by_rays),
      complete_within_(part ? part->complete_within : kInf), jump_(kJumpVoxels * voxel),
      run_most_(kRunVoxels * voxel) {
    if (skip && skip->size() != spans.size()) throw std::logic_error("PointDepths: one flag a group");
    // No group for those measured elsewhere (over MPI, most of the first process's): their
    // memory was a fresh page's fault each (the 50 M-point city block's 1.6 M groups).
    const auto here = [skip](std::size_t g) { return !skip || !(*skip)[g]; };
    std::size_t measured_here = 0;
    for (std::size_t g = 0; g < spans.size(); ++g) measured_here += here(g);
    groups_.resize(measured_here);
    for (std::size_t g = 0, at = 0; g < spans.size(); ++g) {
        if (!here(g)) continue;
        Group& group = groups_[at++];
        group.begin = spans[g].begin;
        group.end = spans[g].end;
        group.lo = spans[g].lo;
        group.hi = spans[g].hi;
        // A part measures no depths for the percentile (the whole cloud's groups are its),
        // but where asked.
        group.sampled = spans[g].sampled && (!part || part->sampled);
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

void PointDepths::bound(std::size_t first, std::size_t last) {
    std::vector<std::uint32_t> ids;
    ids.reserve(last - first);
    for (std::size_t g = first; g < last; ++g) ids.push_back(std::uint32_t(g));
    pass(ids, kInf);
}

void PointDepths::settle(std::size_t first, std::size_t last, double shallowest) {
    std::vector<std::uint32_t> ids;
    for (std::size_t g = first; g < last; ++g) {
        const Group& group = groups_[g];
        if (!group.unresolved && !group.measured && group.side < 0 && group.low < shallowest)
            ids.push_back(std::uint32_t(g));
    }
    pass(ids, shallowest);
}

void PointDepths::pass(const std::vector<std::uint32_t>& ids, double settle_below) {
    std::unique_ptr<DepthScratch> taken;
    {
        const std::lock_guard<std::mutex> lock(scratch_lock_);
        if (!scratches_.empty()) {
            taken = std::move(scratches_.back());
            scratches_.pop_back();
        }
    }
    if (!taken) taken = std::make_unique<DepthScratch>();
    DepthScratch& s = *taken;
    s.start_pass();
    double before = kInf;  // a bound on the last run's centre's distance to the surface
    Vec3 before_at{0, 0, 0};
    for (std::size_t i = 0, end = 0; i < ids.size(); ++i) {
        if (i >= end) {
            // The next run: groups while their box stays small (they come in Morton
            // order, mostly side by side).
            Vec3 lo = groups_[ids[i]].lo, hi = groups_[ids[i]].hi;
            std::size_t points = groups_[ids[i]].end - groups_[ids[i]].begin;
            for (end = i + 1; end < ids.size() && end - i < kRunGroups; ++end) {
                Vec3 l = lo, h = hi;
                for (int a = 0; a < 3; ++a) {
                    l[a] = std::min(l[a], groups_[ids[end]].lo[a]);
                    h[a] = std::max(h[a], groups_[ids[end]].hi[a]);
                }
                if (0.5 * norm(sub(h, l)) > run_most_) break;
                lo = l, hi = h;
                points += groups_[ids[end]].end - groups_[ids[end]].begin;
            }
            // The last run's bound plus the way between them; after a jump, a search of its own.
            const Vec3 centre = mid(lo, hi);
            const double way = norm(sub(centre, before_at));
            const double half = 0.5 * norm(sub(hi, lo));
            // A lone leaf wider than a run (a sparse scan) would gather far too many.
            before = gather(s, centre, half, way <= jump_ ? before + way : kInf,
                            points >= kFewPoints && half <= run_most_);
            before_at = centre;
            // A part's search that went farther than its triangles reach may have missed one.
            s.run_unsure = !(s.run_distance <= complete_within_ && s.run_reach <= complete_within_);
        }
        Group& group = groups_[ids[i]];
        s.unsure = s.run_unsure;
        visit(group, false, settle_below, s);
        group.unresolved = s.unsure;
        if (!group.unresolved) s.shallowest = std::min(s.shallowest, group.shallowest);
    }
    const std::lock_guard<std::mutex> lock(scratch_lock_);
    scratches_.push_back(std::move(taken));
}

double PointDepths::gather(DepthScratch& s, const Vec3& centre, double radius, double bound, bool lanes) const {
    // Each group's nearest triangles lie within d_g + 2 r_g of its centre c_g, and
    // d_g <= d + |c_g - c| for d the run centre's distance: within d + 2 R of the run's
    // centre c, R = |c_g - c| + r_g at most the run box's half diagonal. Any d above the
    // distance serves: next to the last run, the least distance to its candidates (they
    // surround the new centre: 6% above the distance on average in test_point_depths),
    // in the lanes, with the floats' error added as visit() adds it. The grid search it
    // spares took a sixth of the check at 25 M points.
    double d = kInf;
    if (lanes && bound < kInf && s.run_reach >= 0 && s.kept.size() > 0) {
        const Vec3 off = sub(centre, s.run_centre);
        const double big = 2 * std::max(s.kept.reach, norm(off));
        const double least = double(least_over_triangles(s.kept, float(off[0]), float(off[1]), float(off[2])));
        d = std::sqrt(least + 0x1p-18 * big * big) * (1 + 1e-9);
    }
    s.run_centre = centre;
    s.kept.reset(0);
    s.run_reach = -1;  // nothing gathered: the groups search point by point
    if (!(d < kInf && d <= bound)) {  // (none found, or no better than the bound)
        const TriangleGrid::Closest at =
            grid_.closest(s.run_centre, bound < kInf ? bound * bound * (1 + 1e-9) : kInf);
        d = at.triangle != TriangleGrid::none ? std::sqrt(at.dist_sq) * (1 + 1e-9) : bound < kInf ? bound : kInf;
    }
    s.run_distance = d;
    if (!(d < kInf) || !lanes) return d;
    s.run_reach = (d + 2 * radius) * (1 + 1e-9) + 1e-12 * (radius + 1);
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    grid_.near(s.run_centre, s.run_reach, s.near, s.seen);
    s.kept.reset(s.near.size());
    for (std::uint32_t t : s.near) {
        const TriangleFrame& f = s.frames.of(t, mesh_);
        const Vec3 corner = sub(V[T[t][std::size_t(f.first)]], s.run_centre);
        s.kept.reach = std::max(s.kept.reach, f.radius + norm(corner));
        s.kept.add(t, f, corner);
    }
    s.kept.pad();
    return d;
}

double PointDepths::shallowest() const {
    double least = kInf;
    for (const Group& g : groups_)
        if (!g.unresolved) least = std::min(least, g.shallowest);
    return least;
}

PointDepths::Figures PointDepths::figures() const {
    Figures f;
    for (const Group& g : groups_) {
        if (g.unresolved) {
            for (std::uint32_t k = g.begin; k < g.end; ++k) f.unresolved.push_back(k);
            f.unresolved_sampled.resize(f.unresolved.size(), g.sampled);
            continue;
        }
        f.undecided.insert(f.undecided.end(), g.undecided.begin(), g.undecided.end());
        f.undecided_distance.insert(f.undecided_distance.end(), g.undecided_distance.begin(), g.undecided_distance.end());
        f.undecided_sampled.resize(f.undecided.size(), g.sampled);
        f.inside += g.inside;
        f.depth_min = std::min(f.depth_min, g.shallowest);
        f.depths.insert(f.depths.end(), g.depths.begin(), g.depths.end());
    }
    return f;
}

// The distance from p to the surface squared and its nearest triangle, among the kept
// candidates (all within reach of p's group), exactly: in float and lanes first, then in
// double for the least (and any that the floats could not tell from it).
void PointDepths::nearest(const Vec3& p, const Vec3& centre, double within, const DepthScratch& s, double slack,
                          float margin, double& d2, std::uint32_t& triangle) const {
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    d2 = kInf;
    triangle = kNone;
    const auto exact = [&](std::uint32_t t) {
        const double e = point_triangle_dist_sq(p, V[T[t][0]], V[T[t][1]], V[T[t][2]]);
        if (e < d2 || (e == d2 && t < triangle)) d2 = e, triangle = t;
    };
    const Vec3 rel = sub(p, s.run_centre), ref = sub(centre, s.run_centre);
    const Least low = nearest_over_triangles(s.kept, s.tangents.v.data(), float(rel[0]), float(rel[1]), float(rel[2]),
                                             float(ref[0]), float(ref[1]), float(ref[2]),
                                             float(within) * (1 + 0x1p-20f), margin);
    if (low.id[0] == kNone) return;
    // A least value clear of the next by twice the slack is the exact least: only its
    // triangle is measured in double; two near-equal ones (a foot near the edge they share)
    // both; more, every candidate.
    if (double(low.d[1]) - double(low.d[0]) > 2 * slack) {
        exact(low.id[0]);
    } else if (double(low.d[2]) - double(low.d[0]) > 2 * slack) {
        exact(low.id[0]);
        exact(low.id[1]);
    } else {
        for (std::size_t j = 0; j < s.kept.size(); ++j) exact(s.kept.id[j]);
    }
}

int PointDepths::side(const Vec3& p, std::uint32_t triangle) const {
    int side = 0;
    if (!by_rays_ && triangle != kNone) {
        const auto& t = mesh_.triangles[triangle];
        side = face_side(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]);
    }
    if (side != 0 || complete_within_ < kInf) return side;  // a part's rays would leave its triangles
    return ray_side(grid_, p, lo_, hi_);
}

Vec3 PointDepths::ray_toward(const Vec3& p, const Vec3& lo, const Vec3& hi) {
    static const Vec3 dir = [] {
        const Vec3 d{0.5377, 0.3019, 0.7877};
        const double n = norm(d);
        return Vec3{d[0] / n, d[1] / n, d[2] / n};
    }();
    Vec3 toward = dir;
    for (int a = 0; a < 3; ++a)
        if (p[a] - lo[a] < hi[a] - p[a]) toward[a] = -toward[a];
    return toward;
}

// One group's visit: what it takes from the run's candidates, and its steps.
class PointDepths::Visit {
public:
    // The group's candidates from its run's: those within d + 2 r of its centre, d its
    // centre's distance (the least over the run's, all within reach of the run's centre).
    Visit(const PointDepths& depths, Group& group, DepthScratch& s)
        : pd_(depths), group_(group), s_(s), centre_(group.centre()) {
        double radius = 0;
        for (std::uint32_t k = group.begin; k < group.end; ++k)
            radius = std::max(radius, PointTree::dist_sq(pd_.points_.point(k), centre_));
        radius_ = std::sqrt(radius);
        off_ = sub(centre_, s.run_centre);
        const LaneTriangles& kept = s.kept;
        // The floats err by far less than this: every value below (2 R)^2, R the largest
        // coordinate about the run's centre, and rounded a dozen times by 2^-24 of it.
        const double big = 2 * std::max(kept.reach, norm(off_) + radius_);
        slack_ = 0x1p-18 * big * big;
        // The same in distances, for the tangent bounds: above their own rounding (a few
        // 2^-24 of big) and the root of the slack over the least distance there is.
        margin_ = float(0x1p-12 * big);
        // Every candidate's distance from the centre and the tangent plane there; the least
        // bounds the centre's distance.
        if (kept.size() > 0) {
            s.tangents.v.resize(kept.packets() * TangentBounds::kPacket);
            nearest_kept_ = tangents_over_triangles(kept, float(off_[0]), float(off_[1]), float(off_[2]),
                                                    s.tangents.v.data());
            const double root = double(s.tangents.v[nearest_kept_ / 8 * TangentBounds::kPacket + nearest_kept_ % 8]) *
                                (1 + 0x1p-20);
            centre_bound_ = std::sqrt(root * root + slack_) * (1 + 1e-9);
        }
        reach_ = (centre_bound_ + 2 * radius_) * (1 + 1e-9) + 1e-12 * (radius_ + 1);
    }

    // Whether the run gathered every candidate the group can need.
    bool run_covers() const { return norm(off_) * (1 + 1e-9) + reach_ <= s_.run_reach; }

    // Beyond what the run gathered (or it gathered nothing): each point's own search.
    void search_each() {
        start();
        if (!(s_.run_distance < kInf)) {  // no triangle at all: every point outside, infinitely far
            for (std::uint32_t k = group_.begin; k < group_.end; ++k) measured(k, kInf, kNone);
            return;
        }
        const double bound = (s_.run_distance + norm(off_)) * (1 + 1e-9);
        for (std::uint32_t k = group_.begin; k < group_.end; ++k) {
            const Vec3 p = pd_.points_.point(k);
            if (!last_.is(p)) {
                const double own = (bound + norm(sub(p, centre_))) * (1 + 1e-9);
                TriangleGrid::Closest near = pd_.grid_.closest(p, own * own + 1e-300);
                if (near.triangle == TriangleGrid::none) near = pd_.grid_.closest(p);
                if (!(near.dist_sq <= pd_.complete_within_ * pd_.complete_within_)) s_.unsure = true;
                last_ = Last{p, near.dist_sq, near.triangle, 0, true};
            }
            measured(k, last_.d2, last_.triangle);
        }
    }

    // Every point on its own: its exact distance and side.
    void measure_all() {
        start();
        for (std::uint32_t k = group_.begin; k < group_.end; ++k) {
            const Vec3 p = pd_.points_.point(k);
            if (!last_.is(p)) {
                double d2;
                std::uint32_t t;
                pd_.nearest(p, centre_, within(k), s_, slack_, margin_, d2, t);
                last_ = Last{p, d2, t, 0, true};
            }
            measured(k, last_.d2, last_.triangle);
        }
    }

    // For a group all inside: each point whose own tangent bound lies below `below` is
    // measured (a triangle farther than below + r from the centre bounds none of them
    // below it); returns the least bound of the others.
    double point_by_point(double below) {
        const float* tb = s_.tangents.v.data();
        const LaneTriangles& kept = s_.kept;
        const double room = double(margin_) + 1e-6 * (radius_ + centre_bound_);
        const float beyond = float((below + radius_ + room) * (1 + 1e-6));
        s_.packets.clear();
        for (std::size_t p = 0; p < kept.packets(); ++p)
            for (int l = 0; l < 8; ++l)
                if (tb[p * TangentBounds::kPacket + std::size_t(l)] <= beyond) {
                    s_.packets.push_back(std::uint32_t(p));
                    break;
                }
        double rest = kInf;
        for (std::uint32_t k = group_.begin; k < group_.end; ++k) {
            if (k > group_.begin && pd_.points_.xyz[k] == pd_.points_.xyz[k - 1]) continue;  // a copy: nothing new
            const Vec3 p = pd_.points_.point(k), o = sub(p, centre_);
            const double low = double(least_tangent_bound(tb, s_.packets, float(o[0]), float(o[1]), float(o[2]))) - room;
            if (!(low < below)) {
                rest = std::min(rest, low);
                continue;
            }
            double d2;
            std::uint32_t t;
            pd_.nearest(p, centre_, within(k), s_, slack_, margin_, d2, t);
            group_.shallowest = std::min(group_.shallowest, std::sqrt(d2));
        }
        return rest;
    }

    // A bound on every point's distance at once; returns false when it cannot show
    // that nothing crosses the group (then every point is to be measured).
    bool bound_all() {
        const float* tb = s_.tangents.v.data();
        // Each candidate's distance lies above its tangent plane at the centre,
        // D + g . (p - c); split g along n (the gradient of the centre's nearest triangle:
        // nearly every candidate's, on a smooth surface) and across it, and bound each part
        // by the points' extent along n and their distance from the line through the
        // centre along n.
        const auto tangent = [&](std::size_t j, int field) {
            return tb[j / 8 * TangentBounds::kPacket + 8 * field + j % 8];
        };
        const Vec3 n{tangent(nearest_kept_, 1), tangent(nearest_kept_, 2), tangent(nearest_kept_, 3)};
        double along_lo = kInf, along_hi = -kInf, across = 0;
        std::uint32_t ref = group_.begin;  // the point likeliest the shallowest: least along n
        for (std::uint32_t k = group_.begin; k < group_.end; ++k) {
            const Vec3 d = sub(pd_.points_.point(k), centre_);
            const double a = dot(d, n);
            if (a < along_lo) along_lo = a, ref = k;
            along_hi = std::max(along_hi, a);
            across = std::max(across, norm(Vec3{d[0] - a * n[0], d[1] - a * n[1], d[2] - a * n[2]}));
        }
        double low = least_group_bound(s_.kept, tb, float(n[0]), float(n[1]), float(n[2]), float(along_lo),
                                       float(along_hi), float(across));
        // Far above the floats' rounding of D, g and the points, and n's of unit length.
        low -= double(margin_) + 1e-6 * (radius_ + centre_bound_);
        // That point, measured: the group's side when nothing crosses it, and a depth that
        // bounds the shallowest from above (the tighter, the fewer groups settle() measures).
        double d2;
        std::uint32_t t;
        pd_.nearest(pd_.points_.point(ref), centre_, within(ref), s_, slack_, margin_, d2, t);
        const int ref_side = pd_.side(pd_.points_.point(ref), t);
        if (ref_side == 0) return false;  // a part's: a ray would tell, the points one by one
        // Nothing crosses the group when no surface comes within r of its centre (the points
        // lie in that ball, and a segment between two of them with it), or when every point
        // lies farther than 2 r from the surface (two on opposite sides would have it between
        // them, within 2 r of each).
        const double centre_low =
            double(tangent(nearest_kept_, 0)) - double(margin_) - 1e-6 * (radius_ + centre_bound_);
        if (!(centre_low > radius_ || low > 2 * radius_)) return false;
        group_.low = low;
        group_.side = ref_side;
        group_.inside = ref_side < 0 ? group_.end - group_.begin : 0;
        group_.shallowest = ref_side < 0 ? std::sqrt(d2) : kInf;
        // Where the whole group's bound lies below the shallowest depth this pass has
        // measured (which the least depth can only undercut), the points' own bounds,
        // while the run's tangents are at hand: settle() then rarely needs the group.
        if (ref_side < 0 && low < s_.shallowest) group_.low = point_by_point(s_.shallowest);
        return true;
    }

private:
    // Copies of one point lie side by side in tree order (a scan may hold thousands):
    // each takes the one before's distance and side.
    struct Last {
        Vec3 p{};
        double d2 = 0;
        std::uint32_t triangle = kNone;
        int side = 0;
        bool valid = false;
        bool is(const Vec3& q) const { return valid && q == p; }
    };

    void start() {
        group_.undecided.clear();
        group_.undecided_distance.clear();
        group_.inside = 0;
        group_.shallowest = kInf;
        group_.depths.clear();
        group_.measured = true;
    }
    void measured(std::uint32_t k, double d2, std::uint32_t triangle) {
        const Vec3 p = pd_.points_.point(k);
        const double d = std::sqrt(d2);
        const int at = last_.is(p) && last_.side != 0 ? last_.side : pd_.side(p, triangle);
        if (at == 0) {  // a part's: a ray would tell
            group_.undecided.push_back(k);
            group_.undecided_distance.push_back(d);
            return;
        }
        last_.side = at;
        const bool inside = at < 0;
        if (inside) {
            group_.shallowest = std::min(group_.shallowest, d);
            ++group_.inside;
        }
        if (group_.sampled) group_.depths.push_back(inside ? d : -d);
    }
    // Point k's distance to the surface, at most.
    double within(std::uint32_t k) const {
        return (centre_bound_ + std::sqrt(PointTree::dist_sq(pd_.points_.point(k), centre_))) * (1 + 1e-9);
    }

    const PointDepths& pd_;
    Group& group_;
    DepthScratch& s_;
    const Vec3 centre_;
    double radius_ = 0;
    Vec3 off_{};           // the centre from the run's centre
    double slack_ = 0;     // the floats' error in squared distances
    float margin_ = 0;     // and in distances
    double centre_bound_ = kInf;
    std::size_t nearest_kept_ = 0;  // the candidate nearest the centre
    double reach_ = 0;
    Last last_;
};

// The steps: the run's candidates, unless they miss some; every point where asked;
// point by point for settle(); else the group's bound, every point where it fails.
void PointDepths::visit(Group& group, bool every_point, double settle_below, DepthScratch& s) const {
    Visit v(*this, group, s);
    every_point = every_point || every_point_ || group.sampled;
    if (!v.run_covers()) {
        v.search_each();
    } else if (every_point) {
        v.measure_all();
    } else if (settle_below < kInf) {  // all inside, as every group settle() visits
        v.point_by_point(settle_below);
    } else if (!v.bound_all()) {
        v.measure_all();
    }
}

}  // namespace snvr::detail
