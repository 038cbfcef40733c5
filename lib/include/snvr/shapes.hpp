// Point samplers of analytic surfaces: the paper's test shapes, for the bundled
// example, the tests and the benchmarks, and harder inputs for judging
// reconstruction quality (open, non-orientable, thin, noisy, unevenly or sparsely
// sampled, scanned). Each takes `spacing`, the distance between neighbouring
// points; the noise-free ones put every point exactly on the surface. Bad
// arguments throw ParameterError, a spacing that would need more than 2e8 points
// ResourceError.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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

// Two parallel open squares (side `size`, edges along x and y) in the planes
// z = c.z -+ gap/2, each a square grid: two surfaces closer than a thick shell.
PointSet parallel_sheets(const Vec3& c, double size, double gap, double spacing);
// Möbius band around the z axis through c: centre circle of radius R, straight
// rulings of length `width` (< R) turning by half a turn around the circle:
//   x(u, v) = c + R (cos u, sin u, 0) + v (cos(u/2) cos u, cos(u/2) sin u, sin(u/2)),
//   u in [0, 2 pi), |v| <= width / 2.
// Rows of constant v, each uniform in arc length: a square-ish grid of `spacing`.
PointSet mobius_strip(const Vec3& c, double R, double width, double spacing);
// Helicoid along z through c: rulings from the axis out to `radius`, rising by
// `pitch` per turn over `turns` turns, centred at c in height:
//   x(u, v) = c + (v cos u, v sin u, pitch u / (2 pi) - pitch turns / 2),
//   u in [0, 2 pi turns], 0 <= v <= radius.
PointSet helicoid(const Vec3& c, double radius, double pitch, double turns, double spacing);
// sphere(c, r, spacing) with every point moved by isotropic Gaussian noise of
// standard deviation sigma per coordinate (so the radial residual has std sigma).
// Deterministic for a seed, on every platform (own normal deviates from mt19937_64).
PointSet noisy_sphere(const Vec3& c, double r, double spacing, double sigma, std::uint64_t seed = 1);
// points plus fraction x their count of points uniform in their bounding box, as in the
// paper's Fig. 10 (5-15% random points); the same for a given seed on every platform.
PointSet with_outliers(PointSet points, double fraction, std::uint64_t seed = 1);
// Sphere whose points per area fall smoothly (exponentially in z) by the factor
// `ratio` >= 1 from the top pole (spacing `spacing`) to the bottom pole (spacing
// `spacing` * sqrt(ratio)); a Fibonacci lattice with warped heights.
PointSet varying_sphere(const Vec3& c, double r, double spacing, double ratio);
// Ring torus around the z axis through c: centre-circle radius R, tube radius
// r < R; rings of constant tube angle. With a spacing large against the
// reconstruction's offset it is the undersampled closed test shape.
PointSet torus(const Vec3& c, double R, double r, double spacing);
// LiDAR-like scan of an open bumpy terrain: the height field
// z = c.z + lidar_height(x - c.x, y - c.y, size) over the square of side `size`
// around c, scanned along lines of constant y, `line_gap` apart, with points
// `spacing` apart along each line, each then moved along the ray from a scanner
// `size` above c by Gaussian range noise of std range_sigma.
PointSet lidar_scan(const Vec3& c, double size, double spacing, double line_gap, double range_sigma,
                    std::uint64_t seed = 1);
// The terrain of lidar_scan: a few smooth Gaussian bumps and dips, scaled with size.
double lidar_height(double x, double y, double size);

// Exact distance from p to the (noise-free) surface of each shape, for accuracy
// tests. The Möbius band, helicoid and terrain are found numerically (coarse
// search, then golden-section or Newton refinement) to about 1e-12.
double sphere_distance(const Vec3& p, const Vec3& c, double r);
double half_sphere_distance(const Vec3& p, const Vec3& c, double r);
double cube_distance(const Vec3& p, const Vec3& c, double s);
double cylinder_distance(const Vec3& p, const Vec3& c, double r, double ht);
double two_headed_cone_distance(const Vec3& p, const Vec3& c, double r, double ht);
double parallel_sheets_distance(const Vec3& p, const Vec3& c, double size, double gap);
double mobius_strip_distance(const Vec3& p, const Vec3& c, double R, double width);
double helicoid_distance(const Vec3& p, const Vec3& c, double radius, double pitch, double turns);
double torus_distance(const Vec3& p, const Vec3& c, double R, double r);
double lidar_distance(const Vec3& p, const Vec3& c, double size);

// By name, centred at (0.5, 0.5, 0.5) in the unit box. The paper's Table 2 size
// 0.35: "sphere" (radius), "cube" (side), "cylinder" (radius and height),
// "half-sphere" (radius, Fig. 5), "cone" (radius 0.35, height 0.7, Fig. 6).
// Harder inputs: "sheets" (side 0.7, gap 0.06), "mobius" (R 0.3, width 0.25),
// "helicoid" (radius 0.35, pitch 0.2, 3 turns), "noisy-sphere" (radius 0.35,
// sigma 0.3 spacing, seed 1), "varying-sphere" (radius 0.35, density ratio 10),
// "torus" (R 0.3, r 0.12), "lidar" (side 0.7, lines 4 spacings apart, range noise
// 0.1 spacing, seed 1). Throws ParameterError for an unknown name.
PointSet by_name(const std::string& name, double spacing);
// `count` points drawn uniformly at random by area on by_name(name, ...)'s surface (as a
// scanner's returns fall, with no spacing between them): a subset of a sampling 100
// times as dense, drawn without replacement by `seed`. Throws ParameterError for an
// unknown name or a count below 1.
PointSet random_by_name(const std::string& name, std::size_t count, std::uint64_t seed);
// Distance to the noise-free surface of by_name(name, spacing).
std::function<double(const Vec3&)> exact_distance_by_name(const std::string& name, double spacing);
// The names by_name knows, in a fixed order.
std::vector<std::string> names();

// A city block as a mobile and an airborne LiDAR return it, in metres: 4 x 4 lots of 48 m
// between streets 12 m wide (a 252 m square about the origin), one or two box buildings
// a lot, 6 to 45 m high (by `seed`); 70% of the `count` points from a scanner 2.5 m up
// driving every street, a 900-ray profile across the street at each stop (80 m range),
// the rest from flight lines 300 m up every 30 m (a swath of +-30 degrees): ground, walls
// and roofs in scan lines, with the gaps occlusion leaves (no wall behind another, no
// street-side roof, the ground under the eaves); 1 cm range noise. Handed to `emit` in
// chunks of at most 2^20 points as they are made, never held whole.
void city_scan(std::size_t count, std::uint64_t seed, const std::function<void(const PointSet&)>& emit);

}  // namespace snvr::shapes
