#include "geometry/point_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <nanoflann.hpp>

namespace snvr {

namespace {

struct Adaptor {
    const PointSet& pts;
    std::size_t kdtree_get_point_count() const { return pts.size(); }
    double kdtree_get_pt(std::size_t n, std::size_t dim) const { return pts[n][dim]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3, std::uint32_t>;

// Keeps the single nearest point, starting from a caller's bound so the search prunes early.
class NearestWithin {
public:
    explicit NearestWithin(double bound_sq) : best_(bound_sq) {}
    bool full() const { return true; }
    bool addPoint(double d, std::uint32_t n) {
        if (d < best_) {
            best_ = d;
            index_ = n;
        }
        return true;
    }
    double worstDist() const { return best_; }
    PointIndex::Hit hit() const { return {best_, index_}; }

private:
    double best_;
    std::size_t index_ = PointIndex::npos;
};

// Nearest point at a squared distance strictly above zero (skips duplicates of the query).
class NearestDistinct {
public:
    bool full() const { return true; }
    bool addPoint(double d, std::uint32_t) {
        if (d > 0 && d < best_) best_ = d;
        return true;
    }
    double worstDist() const { return best_; }
    double best() const { return best_; }

private:
    double best_ = std::numeric_limits<double>::max();
};

// Hands every point within the radius to a callback, keeping no list.
class WithinRadius {
public:
    WithinRadius(double radius_sq, const std::function<void(std::size_t)>& f) : r_(radius_sq), f_(f) {}
    bool full() const { return true; }
    bool addPoint(double d, std::uint32_t n) {
        if (d < r_) f_(n);
        return true;
    }
    double worstDist() const { return r_; }

private:
    double r_;
    const std::function<void(std::size_t)>& f_;
};

}  // namespace

struct PointIndex::Impl {
    Adaptor adaptor;
    Tree tree;
    explicit Impl(const PointSet& p) : adaptor{p}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

PointIndex::PointIndex(const PointSet& points) : impl_(std::make_unique<Impl>(points)) {}
PointIndex::~PointIndex() = default;

PointIndex::Hit PointIndex::nearest(const Vec3& q, double bound_sq) const {
    NearestWithin result(bound_sq);
    impl_->tree.findNeighbors(result, q.data(), nanoflann::SearchParams());
    return result.hit();
}

const Vec3& PointIndex::point(std::size_t n) const { return impl_->adaptor.pts[n]; }

void PointIndex::for_each_within(const Vec3& q, double radius, const std::function<void(std::size_t)>& f) const {
    WithinRadius result(radius * radius, f);
    impl_->tree.findNeighbors(result, q.data(), nanoflann::SearchParams());
}

double PointIndex::nearest_other(std::size_t n) const {
    NearestDistinct result;
    impl_->tree.findNeighbors(result, impl_->adaptor.pts[n].data(), nanoflann::SearchParams());
    return result.best() == std::numeric_limits<double>::max() ? 0.0 : std::sqrt(result.best());
}

double PointIndex::kth_nearest(std::size_t n, std::size_t k) const {
    const std::size_t want = std::min(k + 1, impl_->adaptor.pts.size());  // the point itself comes first
    std::vector<std::uint32_t> index(want);
    std::vector<double> dist_sq(want);
    nanoflann::KNNResultSet<double, std::uint32_t> result(want);
    result.init(index.data(), dist_sq.data());
    impl_->tree.findNeighbors(result, impl_->adaptor.pts[n].data(), nanoflann::SearchParams());
    return std::sqrt(dist_sq[result.size() - 1]);
}

}  // namespace snvr
