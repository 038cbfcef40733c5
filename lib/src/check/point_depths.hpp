// How deep each point lies below a closed mesh's surface, and which points lie inside
// (point_depths.cpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "geometry/point_tree.hpp"
#include "mesh/triangle_grid.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

struct DepthScratch;   // point_depths.cpp

// The points in groups of neighbours (leaves of the tree, consecutive in its order), each
// group with the triangles that can be nearest to one of its points: within d + 2 r of
// its centre, d the centre's distance to the surface and r the group's radius. A point is
// measured against them in float and in vector lanes, then again in double for the
// nearest: its exact squared distance. But most groups need no point measured: a lower
// bound for the whole group (from the candidates' tangent planes) shows that nothing
// crosses it (all its points share one side, that of the point nearest its centre) and
// how deep its shallowest point can be. bound() visits every group; settle() then
// measures, point by point, the groups whose bound lies below the shallowest depth found
// (one of them holds the shallowest point), so that the least depth is exact. Depths for
// the percentile are measured in every group up to 2^18 points, else in evenly spread
// groups of about that many points in all.
class PointDepths {
public:
    // A part of the points, measured against a part of the mesh (a process's share of a
    // tiled run's check, shared_check.cpp): no depths for the percentile unless asked, and a group
    // is left `unresolved` where the part's triangles cannot decide it (a search beyond
    // complete_within, which the part holds every triangle within, or a side that a ray's
    // crossings would decide).
    struct Part {
        double complete_within = std::numeric_limits<double>::infinity();
        bool sampled = false;  // its sampled groups' depths go to the percentile (the first process's part)
    };
    // every_point: measure every point (and by a ray's crossings when by_rays) rather than
    // only what the figures need. skip: groups (in group_spans()' order) measured
    // elsewhere, none made for them (groups() counts the rest), or null. part: the points
    // and mesh are a part, or null.
    PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel, bool every_point,
                bool by_rays, const std::vector<std::uint8_t>* skip = nullptr, const Part* part = nullptr);
    // A part over groups given as runs [begin, end) of the points' order (another
    // process's kept range, CheckShare::range_groups), their boxes made here.
    PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel,
                const std::vector<std::array<std::uint32_t, 2>>& groups, const Part& part);
    ~PointDepths();

    // The groups as the class makes them: points [begin, end) of the tree, their box, and
    // whether its depths go to the percentile.
    struct Span {
        std::uint32_t begin = 0, end = 0;
        Vec3 lo{0, 0, 0}, hi{0, 0, 0};
        bool sampled = false;
    };
    static std::vector<Span> group_spans(const PointTree& points, double voxel, bool every_point);
    // Points [begin, end) as a group (their box, as group_spans makes it from the leaves').
    static Span span_of(const PointTree& points, std::uint32_t begin, std::uint32_t end);
    // `spans` with each group not sampled whose half diagonal exceeds `widest` cut into
    // runs of consecutive points as narrow as group_spans makes its groups (a sparse
    // scan's lone leaves, a scan line's 30 voxels long: measured as one they need
    // triangles from far around, and another process's share holds only those near).
    static std::vector<Span> narrowed(const PointTree& points, double voxel, double widest, std::vector<Span> spans);
    // The same over the groups group_spans gave for these points, voxel and every_point
    // (made once by a caller that dealt them among processes).
    PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel,
                const std::vector<Span>& spans, bool every_point, bool by_rays, const std::vector<std::uint8_t>* skip,
                const Part* part = nullptr);

    std::size_t groups() const { return groups_.size(); }  // those measured here
    // The first pass over groups [first, last) (disjoint ranges from several threads).
    void bound(std::size_t first, std::size_t last);
    // The shallowest depth measured in the first pass: every bound() done.
    double shallowest() const;
    // The second pass over groups [first, last): those inside with a bound below `shallowest`.
    void settle(std::size_t first, std::size_t last, double shallowest);

    struct Figures {
        std::size_t inside = 0;                                // points inside
        double depth_min = std::numeric_limits<double>::infinity();  // the least depth of a point inside
        std::vector<double> depths;  // signed depths (negative outside) of the points sampled for the percentile
        // Of a part: the points (tree order) whose nearest triangle lies beyond its reach, and
        // those whose distance it measured but whose side only a ray's crossings tell; for
        // each, whether its depth goes to the percentile.
        std::vector<std::uint32_t> unresolved, undecided;
        std::vector<double> undecided_distance;
        std::vector<std::uint8_t> unresolved_sampled, undecided_sampled;
    };
    Figures figures() const;
    // A point's distance to the surface and whether it lies inside (for the points a part
    // left unresolved, as the slabs answer: slab_queries.hpp).
    struct Depth {
        double distance = 0;
        bool inside = false;
    };
    // The direction of the rays whose crossings tell a side: one that no grid-aligned edge
    // of a marching-cubes mesh is parallel to, heading for the nearer face of the mesh's
    // box [lo, hi] on every axis to cut the walk short.
    static Vec3 ray_toward(const Vec3& p, const Vec3& lo, const Vec3& hi);

private:
    // Points [begin, end) of the tree, within the box [lo, hi], and what is known of them.
    struct Group {
        std::uint32_t begin = 0, end = 0;
        Vec3 lo{0, 0, 0}, hi{0, 0, 0};
        bool sampled = false;   // its depths go to the percentile
        bool measured = false;  // point by point
        bool unresolved = false;  // a part's triangles could not decide it
        std::vector<std::uint32_t> undecided;  // nor these points' sides
        std::vector<double> undecided_distance;  // but their distances
        int side = 0;           // +1 all outside, -1 all inside, 0 not known as a whole
        double low = -std::numeric_limits<double>::infinity();  // no point nearer the surface
        double shallowest = std::numeric_limits<double>::infinity();  // least depth measured inside
        std::size_t inside = 0;
        std::vector<double> depths;  // when sampled
        Vec3 centre() const { return {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])}; }
    };
    // Visits the groups `ids` (ascending) in runs of neighbours; settle_below as visit's.
    void pass(const std::vector<std::uint32_t>& ids, double settle_below);
    // Gathers into the scratch the candidate triangles of a run of groups, all within
    // `radius` of `centre`, given a bound on the centre's distance to the surface (or
    // infinity); without `lanes`, only that bound (the groups then search point by point).
    // Returns a (tighter) bound on that distance.
    double gather(DepthScratch& scratch, const Vec3& centre, double radius, double bound, bool lanes) const;
    // One group of the gathered run; every_point to measure each point. With settle_below
    // finite, a group known to lie inside as a whole: each point whose bound lies below
    // it is measured, for the shallowest.
    void visit(Group& group, bool every_point, double settle_below, DepthScratch& scratch) const;
    class Visit;  // one visit's state and steps
    // p's exact squared distance to the surface and nearest triangle, among the
    // candidates the scratch holds for p's group (centre), p's distance at most `within`.
    void nearest(const Vec3& p, const Vec3& centre, double within, const DepthScratch& scratch, double slack, float margin,
                 double& d2, std::uint32_t& triangle) const;
    // -1 inside, +1 outside: by the nearest triangle's side where p's foot lies clear
    // inside its face, else (or always, by_rays) by a ray's crossings; 0 where a part
    // would need the ray.
    int side(const Vec3& p, std::uint32_t triangle) const;

    const Mesh& mesh_;
    const TriangleGrid& grid_;
    const PointTree& points_;
    bool every_point_, by_rays_;
    double complete_within_;  // a part's: searches beyond this leave a group unresolved
    double jump_;      // beyond this from the last run, a fresh search
    double run_most_;  // the half diagonal of a run's box, at most
    std::vector<Group> groups_;
    Vec3 lo_{0, 0, 0}, hi_{0, 0, 0};  // the mesh's box, for the rays' directions
    // The passes' working spaces, each taken by one pass at a time and kept for the next
    // (their arrays grow to a run's triangles once, not in every chunk of groups).
    mutable std::mutex scratch_lock_;
    mutable std::vector<std::unique_ptr<DepthScratch>> scratches_;
};

}  // namespace snvr::detail
