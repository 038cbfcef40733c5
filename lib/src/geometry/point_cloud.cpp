// PointCloud (point_cloud.hpp): the handle on a PointTree; the choice of origin.
#include "snvr/point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "geometry/point_tree.hpp"
#include "geometry/vec3_math.hpp"
#include "number_text.hpp"
#include "snvr/error.hpp"
#include "parallel_sizes.hpp"

namespace snvr {
namespace {

[[noreturn]] void non_finite(std::size_t i, const Vec3& p) {
    throw InputError("point " + std::to_string(i) + " has a non-finite coordinate (" + detail::format_number(p[0]) +
                     " " + detail::format_number(p[1]) + " " + detail::format_number(p[2]) + ")");
}

bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

// Points 1e308 and -1e308 apart span more than float coordinates about any origin hold:
// the two outermost points along the axis are named. `at(i)` gives point i.
template <class At>
[[noreturn]] void too_far(std::size_t n, const At& at, int a) {
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (at(i)[a] < at(lo)[a]) lo = i;
        if (at(i)[a] > at(hi)[a]) hi = i;
    }
    const std::string axis(1, "xyz"[a]);
    throw InputError("the points span more than float coordinates can hold along " + axis + ": point " +
                     std::to_string(lo) + " at " + axis + " = " + detail::format_number(at(lo)[a]) + " and point " +
                     std::to_string(hi) + " at " + axis + " = " + detail::format_number(at(hi)[a]) +
                     " (points are counted from 0); remove the stray points");
}

// 0 where float holds the points as they are, or they lie near the world origin;
// else their round centre, so that floats keep their digits. In parallel: a scan's
// millions of points pass here once.
template <class At>
Vec3 choose_origin(std::size_t n, const At& at) {
    if (n == 0) return {0, 0, 0};
    bool floats = true;
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = hi[a] = at(0)[a];
    const std::ptrdiff_t count = std::ptrdiff_t(n);
#pragma omp parallel for reduction(&& : floats) reduction(min : lo[:3]) reduction(max : hi[:3]) schedule(static) \
    if (count > detail::kParallelCheapItems)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
        const Vec3 p = at(std::size_t(i));
        for (int a = 0; a < 3; ++a) {
            floats = floats && double(float(p[a])) == p[a];
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    if (floats) return {0, 0, 0};
    Bounds box;
    for (int a = 0; a < 3; ++a) box.lo[a] = lo[a], box.hi[a] = hi[a];
    double far = 0;
    for (int a = 0; a < 3; ++a) far = std::max(far, std::abs(box.lo[a] / 2 + box.hi[a] / 2));
    return far <= box.longest() ? Vec3{0, 0, 0} : round_centre(box);
}

// The tree of n points, point i being at(i) in world units.
template <class At>
std::unique_ptr<detail::PointTree> file_points(std::size_t n, const At& at) {
    detail::require_point_count(n);
    const std::ptrdiff_t count = std::ptrdiff_t(n);
    std::ptrdiff_t first_bad = count;  // the first non-finite point, named as the serial scan would
#pragma omp parallel for reduction(min : first_bad) schedule(static) if (count > detail::kParallelCheapItems)
    for (std::ptrdiff_t i = 0; i < count; ++i)
        if (!finite(at(std::size_t(i)))) first_bad = std::min(first_bad, i);
    if (first_bad < count) non_finite(std::size_t(first_bad), at(std::size_t(first_bad)));
    const Vec3 origin = choose_origin(n, at);
    detail::PointArray<Vec3f> xyz(n);
    int beyond = -1;  // an axis some point cannot be held along, about the origin
#pragma omp parallel for reduction(max : beyond) schedule(static) if (count > detail::kParallelCheapItems)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
        const Vec3 p = at(std::size_t(i));
        for (int a = 0; a < 3; ++a) {
            xyz[std::size_t(i)][a] = float(p[a] - origin[a]);
            if (!std::isfinite(xyz[std::size_t(i)][a])) beyond = std::max(beyond, a);
        }
    }
    if (beyond >= 0) too_far(n, at, beyond);
    return std::make_unique<detail::PointTree>(std::move(xyz), detail::PointArray<std::uint32_t>(), origin);
}

template <class Real>
std::unique_ptr<detail::PointTree> file_array(const Real* xyz, std::size_t n) {
    return file_points(n, [xyz](std::size_t i) {
        return Vec3{double(xyz[3 * i]), double(xyz[3 * i + 1]), double(xyz[3 * i + 2])};
    });
}

// Float coordinates about an origin, checked, then filed by `file`.
std::unique_ptr<detail::PointTree> file_coordinates(detail::PointArray<Vec3f> coordinates, const Vec3& origin,
                                                    const detail::TreeFiler& file) {
    detail::require_point_count(coordinates.size());
    if (!finite(origin)) throw InputError("the points' origin is not finite");
    for (std::size_t i = 0; i < coordinates.size(); ++i) {
        const Vec3f& c = coordinates[i];
        if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
            non_finite(i, {origin[0] + c[0], origin[1] + c[1], origin[2] + c[2]});
    }
    return file(std::move(coordinates), origin);
}

}  // namespace

std::size_t PointCloud::bytes() const {
    return tree_->xyz.capacity() * sizeof(Vec3f) + tree_->input.capacity() * sizeof(std::uint32_t) +
           tree_->nodes.capacity() * sizeof(detail::PointTree::Node);
}

std::size_t detail::heap_bytes(const PointCloud& cloud) {
    const PointTree& t = tree_of(cloud);
    const auto on_heap = [](const auto& array) {
        return spilled(array.data()) ? 0 : array.capacity() * sizeof(array[0]);
    };
    return on_heap(t.xyz) + on_heap(t.input) + on_heap(t.nodes);
}

PointCloud::PointCloud() : tree_(std::make_unique<detail::PointTree>()) {}

PointCloud::PointCloud(const PointSet& points)
    : tree_(file_points(points.size(), [&points](std::size_t i) { return points[i]; })) {}

PointCloud::PointCloud(const double* xyz, std::size_t n) : tree_(file_array(xyz, n)) {}
PointCloud::PointCloud(const float* xyz, std::size_t n) : tree_(file_array(xyz, n)) {}

PointCloud::PointCloud(std::vector<Vec3f> coordinates, const Vec3& origin)
    : PointCloud(detail::cloud_of(detail::PointArray<Vec3f>(coordinates.begin(), coordinates.end()), origin, nullptr)) {}

PointCloud detail::cloud_of(PointArray<Vec3f>&& coordinates, const Vec3& origin, const PointTree::Frame* frame) {
    return cloud_filed(std::move(coordinates), origin, [frame](PointArray<Vec3f>&& xyz, const Vec3& at) {
        return std::make_unique<PointTree>(std::move(xyz), PointArray<std::uint32_t>(), at, frame);
    });
}

void detail::require_point_count(std::size_t n) {
    if (n >= std::size_t(std::numeric_limits<std::uint32_t>::max()))
        throw ResourceError("a point cloud holds at most 4,294,967,294 points, not " + std::to_string(n));
}

PointCloud detail::cloud_filed(PointArray<Vec3f>&& coordinates, const Vec3& origin, const TreeFiler& file) {
    PointCloud cloud;
    CloudAccess::tree_of(cloud) = file_coordinates(std::move(coordinates), origin, file);
    return cloud;
}

PointCloud detail::cloud_with(const PointCloud& points, const PointSet& more) {
    const PointTree& t = tree_of(points);
    const std::size_t n = t.size(), all = n + more.size();
    const auto afresh = [&] {
        PointSet joined = points.to_point_set();
        joined.insert(joined.end(), more.begin(), more.end());
        return PointCloud(joined);
    };
    // The points' ranks by input (as to_point_set numbers them) from the indices dropped.
    if (all == 0 || !t.numbering_known() || all >= std::size_t(std::numeric_limits<std::uint32_t>::max()))
        return afresh();
    const auto at = [&](std::size_t i) { return i < n ? t.point(i) : more[i - n]; };
    for (const Vec3& p : more)
        if (!finite(p)) return afresh();  // its error, naming the point as it counts them
    const Vec3 origin = choose_origin(all, at);
    PointArray<Vec3f> xyz(all);
    bool held = true;
    const std::ptrdiff_t count = std::ptrdiff_t(all);
#pragma omp parallel for reduction(&& : held) schedule(static) if (count > detail::kParallelCheapItems)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
        const Vec3 p = at(std::size_t(i));
        for (int a = 0; a < 3; ++a) {
            xyz[std::size_t(i)][a] = float(p[a] - origin[a]);
            held = held && std::isfinite(xyz[std::size_t(i)][a]);
        }
    }
    if (!held) return afresh();
    const PointTree::Frame frame = PointTree::filing_of(xyz).frame;
    PointArray<std::uint64_t> key(all);
    PointArray<std::uint32_t> rank(all);
    const std::vector<std::uint32_t>& dropped = t.inputs_dropped;
#pragma omp parallel for schedule(static) if (count > detail::kParallelCheapItems)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
        const std::size_t i = std::size_t(s);
        key[i] = frame.key(xyz[i]);
        if (i < n) {
            const std::uint32_t in = t.input[i];
            rank[i] = in - std::uint32_t(std::lower_bound(dropped.begin(), dropped.end(), in) - dropped.begin());
        } else {
            rank[i] = std::uint32_t(i);
        }
    }
    // Filing sorts by key, ties by rank: the points must already be in that order.
    for (std::size_t i = 1; i < n; ++i)
        if (key[i] < key[i - 1] || (key[i] == key[i - 1] && rank[i] < rank[i - 1])) return afresh();
    std::vector<std::uint32_t> extra(more.size());
    std::iota(extra.begin(), extra.end(), std::uint32_t(n));
    const auto before = [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b] || (key[a] == key[b] && a < b); };
    std::sort(extra.begin(), extra.end(), before);
    PointArray<Vec3f> sorted(all);
    PointArray<std::uint32_t> input(all);
    PointArray<std::uint64_t> keys(all);
    std::size_t i = 0, j = 0;
    for (std::size_t to = 0; to < all; ++to) {
        // At equal keys the points first: their ranks are below every added one's.
        const bool from_points = j == extra.size() || (i < n && key[i] <= key[extra[j]]);
        const std::size_t from = from_points ? i++ : extra[j++];
        sorted[to] = xyz[from];
        input[to] = rank[from];
        keys[to] = key[from];
    }
    PointCloud cloud;
    auto& tree = CloudAccess::tree_of(cloud);
    tree = std::make_unique<PointTree>(std::move(sorted), std::move(input), origin, frame, keys.data());
    tree->numbered_whole();
    return cloud;
}

PointCloud detail::cloud_of_flat(std::vector<float>&& xyz, const Vec3& origin, const PointTree::Frame* frame) {
    if (xyz.size() % 3) throw InputError("points sent as x y z in turn are not whole");
    PointArray<Vec3f> points(xyz.size() / 3);
    if (!points.empty()) std::memcpy(points.data(), xyz.data(), xyz.size() * sizeof(float));
    std::vector<float>().swap(xyz);
    return cloud_of(std::move(points), origin, frame);
}

// A copy is filed by this process alone: the others' ranges are the original's.
PointCloud::PointCloud(const PointCloud& other) : tree_(std::make_unique<detail::PointTree>(*other.tree_)) {
    tree_->filed_alone();
}
PointCloud& PointCloud::operator=(const PointCloud& other) {
    if (this != &other) {
        tree_ = std::make_unique<detail::PointTree>(*other.tree_);
        tree_->filed_alone();
    }
    return *this;
}
PointCloud::PointCloud(PointCloud&& other) noexcept : tree_(std::move(other.tree_)) {
    other.tree_ = std::make_unique<detail::PointTree>();
}
PointCloud& PointCloud::operator=(PointCloud&& other) noexcept {
    std::swap(tree_, other.tree_);
    return *this;
}
PointCloud::~PointCloud() = default;

std::size_t PointCloud::size() const { return tree_->size(); }
Vec3 PointCloud::operator[](std::size_t k) const { return tree_->point(k); }
std::size_t PointCloud::input_index(std::size_t k) const { return tree_->input[k]; }
const Vec3& PointCloud::origin() const { return tree_->origin; }

std::array<Vec3, 2> PointCloud::box() const {
    if (tree_->nodes.empty()) return {tree_->origin, tree_->origin};
    return {tree_->lo(tree_->nodes[0]), tree_->hi(tree_->nodes[0])};
}

PointSet PointCloud::to_point_set() const {
    // Input indices may have gaps (points dropped): they keep their order.
    std::vector<std::uint32_t> order(size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return tree_->input[a] < tree_->input[b]; });
    PointSet out(size());
    for (std::size_t i = 0; i < order.size(); ++i) out[i] = tree_->point(order[i]);
    return out;
}

void PointCloud::keep(const std::vector<std::uint8_t>& flags) {
    if (flags.size() != size()) throw ParameterError("PointCloud::keep: one flag a point");
    if (std::find(flags.begin(), flags.end(), 0) == flags.end()) return;
    tree_->keep_only(flags);
}

void PointCloud::scale(double factor) {
    if (!(factor > 0) || !std::isfinite(factor)) throw ParameterError("a point cloud's scale factor must be positive");
    if (factor != 1) tree_->scale(factor);
}

void PointCloud::translate(const Vec3& by) {
    for (int a = 0; a < 3; ++a) tree_->origin[a] += by[a];
}

}  // namespace snvr
