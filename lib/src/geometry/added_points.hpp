// The points the distance is measured to: the input's, and those added on the surface
// they describe (Parameters::add_points): at the centres of a random sampling's holes
// (sampling_holes.hpp) and between points sparser than the offset (surface_upsampling.hpp).
#pragma once
#include <cstddef>
#include <functional>

#include "geometry/sampling_holes.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

struct AddedPoints {
    std::size_t at_holes = 0;  // at the centres of holes wider than hole_least
    std::size_t between = 0;   // upsample_spacing apart between the points
};

// `points` and the points added to them: at the centres of the holes wider than
// hole_least (0: none looked for), then every upsample_spacing on the surface of those
// (0: none), none farther than `slack` outside the points' box (the surface between the
// outermost points bulges out of their box a little; the grid's padding holds that much,
// and no point far out of place). Empty when none was added (`added` says how many).
// `ways` says how the work is shared and told (each optional): `between` makes the points
// between (upsample_surface over the cloud it is given at upsample_spacing, however it
// shares the work); `holes` finds the holes at some of the points elsewhere
// (hole_centres'); `holes_told` hears how far their search has gone.
using MakePointsBetween = std::function<PointSet(const PointCloud& so_far)>;
struct AddingWays {
    MakePointsBetween between;
    AskHoles holes;
    HolesTold holes_told;
};
PointCloud with_added_points(const PointCloud& points, double hole_least, double upsample_spacing, double slack,
                             AddedPoints& added, const AddingWays& ways = {});

}  // namespace snvr
