// Point samplers of analytic surfaces: the paper's test shapes, for the bundled
// example, the tests and the benchmarks. Points lie exactly on the surface.
#pragma once
#include <string>

#include "snvr/geometry.hpp"

namespace snvr::shapes {

// Sphere of radius r centred at c, roughly uniform with the given spacing.
PointSet sphere(const Vec3& c, double r, double spacing);
// Upper half (z >= c.z) of that sphere: an open surface (paper Fig. 5).
PointSet half_sphere(const Vec3& c, double r, double spacing);
// Surface of the axis-aligned cube of side s centred at c, a grid of spacing.
PointSet cube(const Vec3& c, double s, double spacing);
// Closed cylinder (side and both caps) along z, radius r, height ht, centred at c.
PointSet cylinder(const Vec3& c, double r, double ht, double spacing);
// Two cones joined at their bases (paper Fig. 6): radius r, total height ht, along z.
PointSet two_headed_cone(const Vec3& c, double r, double ht, double spacing);

// Exact distance from p to the surface of each shape (for accuracy tests).
double sphere_distance(const Vec3& p, const Vec3& c, double r);
double cube_distance(const Vec3& p, const Vec3& c, double s);
double cylinder_distance(const Vec3& p, const Vec3& c, double r, double ht);

// By name, centred at (0.5, 0.5, 0.5) in the unit box with the paper's Table 2
// size 0.35: "sphere" (radius), "cube" (side), "cylinder" (radius and height),
// "half-sphere" (radius, Fig. 5), "cone" (radius 0.35, height 0.7, Fig. 6).
// Throws ParameterError for an unknown name.
PointSet by_name(const std::string& name, double spacing);

}  // namespace snvr::shapes
