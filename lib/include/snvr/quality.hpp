// Figures that judge a reconstructed shell against its input points, the offset l
// and the voxel size h: pieces and genus, how deep the points sit inside, how far
// the surface is from l, how smooth it is and how thin its walls get.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/tiles.hpp"

namespace snvr {

struct MeshReport {
    std::size_t vertices = 0, triangles = 0;
    std::size_t boundary_edges = 0;     // edges with one incident triangle
    std::size_t nonmanifold_edges = 0;  // edges with more than two incident triangles
    std::size_t misoriented_edges = 0;  // interior edges whose two triangles traverse it the same way
    std::size_t nonmanifold_vertices = 0;  // vertices whose triangle fan is not a single disc
    std::size_t degenerate_triangles = 0;  // repeated vertex indices
    std::size_t zero_area_triangles = 0;   // three vertices, but on one line or two at one place
    std::size_t components = 0;            // edge-connected pieces
    std::size_t solids = 0;                // pieces enclosing positive volume: separate solid
                                           // parts (the other pieces bound cavities in them)
    double volume = 0;  // signed enclosed volume (positive when outward oriented)
    bool closed() const { return triangles > 0 && boundary_edges == 0; }
    bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0 && degenerate_triangles == 0; }
    bool oriented() const { return misoriented_edges == 0 && volume > 0; }
};

MeshReport check_mesh(const Mesh& mesh);

// How far two meshes of one surface are from each other (a tiled run's and a whole one's):
// from each vertex of either, the distance to the nearest vertex of the other; the
// largest and the RMS over both sets, world units.
struct VertexDistance {
    double max = 0, rms = 0;
};
VertexDistance vertex_distance(const Mesh& a, const Mesh& b);

// Lengths are in the units named by each field: "h" (voxel), "l" (offset),
// "2l" (the shell's intended thickness) or degrees. NaN marks a figure with no
// data (say, depth when no point is inside).
struct MeshQuality {
    std::size_t vertices = 0, triangles = 0, points = 0;
    double offset = 0, voxel = 0;  // l and h as given, world units

    MeshReport report;           // check_mesh's full report (counts of every defect)
    std::size_t components = 0;  // edge-connected pieces of the mesh (check_mesh)
    std::size_t solids = 0;      // pieces enclosing positive volume (check_mesh)
    std::size_t cavities = 0;    // components - solids: pieces bounding holes inside solids
    bool closed = false, manifold = false, oriented = false;  // check_mesh's verdicts
    long genus = 0;                    // sum over closed components of (2 - V + E - F) / 2
    std::size_t open_components = 0;  // components with boundary edges (left out of genus)

    std::size_t points_inside = 0;   // input points strictly inside the solid (count_points_inside;
                                     // measure_shell: by the nearest triangle's side, else a ray)
    std::size_t points_outside = 0;  // points - points_inside
    double inside_fraction = 0;      // points_inside / points
    double depth_min = 0;  // over l: smallest distance to the surface of a point inside
    double depth_p01 = 0;  // over l: 1st percentile over all points of the signed depth (outside < 0)
    std::size_t inside_disagreements = 0;  // |inside by ray parity (which picks the points for
                                           // depth_min) - points_inside|: should be 0

    bool has_surface = false;  // the surface figures below were measured (measure_quality, not measure_shell)

    double offset_rms = 0;   // over vertices, RMS of e = (distance to nearest point) - l, in h
    double offset_mean = 0;  // mean of e, in h
    double offset_max = 0;   // max |e|, in h

    double dihedral_rms = 0;  // degrees; area-weighted RMS of the normals' angle over interior edges
    std::size_t interior_edges = 0;  // edges with exactly two triangles
    double normal_noise = 0;  // degrees; RMS over vertices of the angle between the vertex
                              // normal and the mean of its 1-ring neighbours' normals

    double wall_min = 0, wall_p01 = 0;        // thickness along the inward normal, in h
    double wall_min_2l = 0, wall_p01_2l = 0;  // the same over 2l
    std::size_t wall_misses = 0;              // vertices whose inward ray meets nothing (at a saddle-like
                                              // crease -normal can point out of the solid)
    std::string walls_on = "host";            // where the walls' rays were cast: the host, or an OpenCL
                                              // device (by a rule on the device the run used: make_shell)

    bool has_exact = false;  // the exact figures below were computed
    double exact_rms = 0;    // RMS over vertices of |exact(v)|, in h
    double exact_max = 0;    // max over vertices of |exact(v)|, in h

    double seconds = 0;  // time measure_quality took
};

// Measures `mesh` (closed, triangles counter-clockwise seen from outside) against the
// points it was built from, the offset l and the voxel size h (both world units).
// `exact`, if given, is the distance from a point to the exact offset surface (0 on
// it); it is called from several threads at once. Throws InputError for triangles
// with out-of-range indices, ParameterError for offset or voxel <= 0.
MeshQuality measure_quality(const Mesh& mesh, const PointCloud& points, double offset, double voxel,
                            const std::function<double(const Vec3&)>& exact = {});
MeshQuality measure_quality(const Mesh& mesh, const PointSet& points, double offset, double voxel,
                            const std::function<double(const Vec3&)>& exact = {});  // makes a PointCloud

// The figures a print needs, at about 0.7x measure_quality's cost: the verdicts,
// pieces and genus, the points inside and their depth, the walls. The surface
// figures (offset error, smoothness) and the second inside test are left out:
// has_surface is false, those figures NaN or 0.
MeshQuality measure_shell(const Mesh& mesh, const PointCloud& points, double offset, double voxel);
MeshQuality measure_shell(const Mesh& mesh, const PointSet& points, double offset, double voxel);  // makes a PointCloud

// Another process's share of the check (tiles.hpp): each measured vertex's wall as the
// whole shell measures it, NaN where the first hit lies beyond the share's reach (or none
// lies within it), infinity where the normal vanishes; and its points' count inside and
// least depth, as the whole shell decides them, but for those it names as unresolved.
// Throws InputError for indices the share lacks, or point groups that do not count its
// points.
CheckShareFigures measure_check_share(CheckShare share);

// Smallest wall thickness of the mesh in world units: from each vertex along its
// inward normal to the first surface met (infinity if no ray meets anything).
// The cheap part of measure_quality, for a closing summary.
double thinnest_wall(const Mesh& mesh);

// What keeps a shell from being the print the points ask for, one sentence each (none:
// nothing): more solid pieces than the points have clusters at twice the offset (the
// shell fell apart; components that bound cavities are fine), an open, non-manifold
// or misoriented mesh, points left outside (said to be expected when dropped_pieces,
// filter_pieces's count, is not 0). `clusters`: count_point_clusters(points, 2 l).
std::vector<std::string> shell_warnings(const MeshQuality& q, std::size_t points, std::size_t clusters,
                                        std::size_t dropped_pieces = 0);

// One readable block, several lines, ending with a newline.
std::string format_quality(const MeshQuality& q);
// The same figures as one line of JSON (no newline); NaN and infinity become null.
std::string quality_json(const MeshQuality& q);

}  // namespace snvr
