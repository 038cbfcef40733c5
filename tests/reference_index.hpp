// A nearest-point index for the tests' reference implementations: nanoflann's kd-tree,
// independent of the library's own tree, over points kept by reference.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>

#include "snvr/geometry.hpp"

namespace snvr::reference {

class Index {
public:
    static constexpr std::size_t npos = std::size_t(-1);
    struct Hit {
        double dist_sq;     // the bound when nothing was found
        std::size_t index;  // npos when nothing was found
    };

    explicit Index(const PointSet& points) : adaptor_{points}, tree_(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}

    const Vec3& point(std::size_t n) const { return adaptor_.points[n]; }

    // The nearest point nearer than sqrt(bound_sq).
    Hit nearest(const Vec3& q, double bound_sq) const {
        Nearest r(bound_sq);
        tree_.findNeighbors(r, q.data(), nanoflann::SearchParams());
        return {r.best, r.index};
    }
    // The distance to the nearest point at a distance above 0 (0 for none).
    double nearest_other(std::size_t n) const {
        Distinct r;
        tree_.findNeighbors(r, point(n).data(), nanoflann::SearchParams());
        return r.best < std::numeric_limits<double>::max() ? std::sqrt(r.best) : 0.0;
    }
    // f(index) for every point nearer than `radius`.
    template <class F>
    void for_each_within(const Vec3& q, double radius, F f) const {
        Within<F> r{radius * radius, f};
        tree_.findNeighbors(r, q.data(), nanoflann::SearchParams());
    }

private:
    struct Adaptor {
        const PointSet& points;
        std::size_t kdtree_get_point_count() const { return points.size(); }
        double kdtree_get_pt(std::size_t n, std::size_t d) const { return points[n][d]; }
        template <class Box>
        bool kdtree_get_bbox(Box&) const { return false; }
    };
    using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3,
                                                     std::uint32_t>;
    struct Nearest {
        double best;
        std::size_t index = npos;
        explicit Nearest(double bound) : best(bound) {}
        bool full() const { return true; }
        bool addPoint(double d, std::uint32_t n) {
            if (d < best) best = d, index = n;
            return true;
        }
        double worstDist() const { return best; }
    };
    struct Distinct {
        double best = std::numeric_limits<double>::max();
        bool full() const { return true; }
        bool addPoint(double d, std::uint32_t) {
            if (d > 0 && d < best) best = d;
            return true;
        }
        double worstDist() const { return best; }
    };
    template <class F>
    struct Within {
        double r;
        F& f;
        bool full() const { return true; }
        bool addPoint(double d, std::uint32_t n) {
            if (d < r) f(std::size_t(n));
            return true;
        }
        double worstDist() const { return r; }
    };

    Adaptor adaptor_;
    Tree tree_;
};

}  // namespace snvr::reference
