// Isosurface extraction and the checks that make a mesh printable.
#pragma once
#include <cstddef>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"

namespace snvr {

// Marching cubes on the cell-centred grid (sample points are cell centres).
// Vertices are welded per grid edge; triangles face from `field > iso` towards
// `field < iso`, i.e. outward for a solid where the field is positive.
// Closed and manifold whenever the field is below `iso` on the whole grid boundary.
Mesh extract_isosurface(const Field& field, const Domain& domain, double iso = 0.0);

struct MeshReport {
    std::size_t vertices = 0, triangles = 0;
    std::size_t boundary_edges = 0;     // edges with one incident triangle
    std::size_t nonmanifold_edges = 0;  // edges with more than two incident triangles
    std::size_t misoriented_edges = 0;  // interior edges whose two triangles traverse it the same way
    std::size_t nonmanifold_vertices = 0;  // vertices whose triangle fan is not a single disc
    std::size_t degenerate_triangles = 0;  // repeated vertex indices
    std::size_t components = 0;            // edge-connected pieces
    double volume = 0;  // signed enclosed volume (positive when outward oriented)
    bool closed() const { return triangles > 0 && boundary_edges == 0; }
    bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0 && degenerate_triangles == 0; }
    bool oriented() const { return misoriented_edges == 0 && volume > 0; }
};

MeshReport check_mesh(const Mesh& mesh);

// How many of the points lie strictly inside the closed mesh (generalised winding number > 1/2).
std::size_t count_points_inside(const Mesh& mesh, const PointSet& points);

}  // namespace snvr
