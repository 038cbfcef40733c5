// The piece count the points suggest, used to warn when a shell breaks apart.
#include <doctest/doctest.h>

#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;

TEST_CASE("clusters of points linked below a distance") {
    PointSet points = shapes::sphere({0, 0, 0}, 1.0, 0.05);
    const PointSet other = shapes::sphere({3, 0, 0}, 0.5, 0.05);
    points.insert(points.end(), other.begin(), other.end());
    CHECK(count_point_clusters(points, 0.2) == 2);   // two separate spheres
    CHECK(count_point_clusters(points, 2.0) == 1);   // linked across the 1.5 gap
    CHECK(count_point_clusters(points, 1e-6) == points.size());  // nothing linked
    CHECK(count_point_clusters({}, 1.0) == 0);
}
