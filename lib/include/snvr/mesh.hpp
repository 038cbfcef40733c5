// Operations on meshes (lib/src/mesh/): isosurface extraction, fairing, the depth guard,
// pieces. Reading and writing them: mesh_io.hpp; checking them: quality.hpp.
#pragma once
#include <cstddef>
#include <limits>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

// Where along a grid edge the surface crosses.
enum class Interpolation {
    Linear,      // the linear interpolant of the samples crosses iso
    PhaseField,  // the field is a tanh profile of a signed distance (a phase field, with
                 // iso = 0): cut where atanh(field) crosses zero, which is exact wherever
                 // the distance is linear along the edge (8x smaller vertex errors than
                 // Linear on the initial field of the paper's 128^3 sphere)
};

// Marching tetrahedra on the cell-centred grid (sample points are cell centres).
// Vertices are welded per grid edge; triangles face from `field > iso` towards
// `field < iso`, i.e. outward for a solid where the field is positive.
// Closed and manifold whenever the field is below `iso` on the whole grid boundary.
Mesh extract_isosurface(const Field& field, const Domain& domain, double iso = 0.0,
                        Interpolation interpolation = Interpolation::Linear);

// Dual marching cubes on the same grid: one vertex per surface patch of each grid cube
// (the mean of the patch's edge crossings), one quad (two triangles) across each
// sign-changing grid edge, about a third of extract_isosurface's triangles.  Ambiguous
// cube faces follow the asymptotic decider, evaluated on the field as interpolated
// (on atanh of it for PhaseField).  Triangles face from `field > iso` towards
// `field <= iso`.  Always closed, 2-manifold and consistently oriented.
// Precondition: no grid edge on the boundary of the grid changes sign (e.g. the field
// is <= iso on the whole grid boundary); otherwise throws InputError.
Mesh extract_dual_isosurface(const Field& field, const Domain& domain, double iso = 0.0,
                             Interpolation interpolation = Interpolation::PhaseField);

// Taubin's lambda|mu smoothing of the vertex positions (lib/src/mesh/mesh_fairing.cpp):
// damps what is a few vertices across, keeps larger shapes where they are (no shrinking).
// The default mesher runs it before the depth guard: on the bunny at 512 cells
// (l = 5 voxels) two passes took the normal noise from 1.55 to 1.45 deg and the
// dihedral from 3.75 to 3.51 deg, and moved the offset error by 0.002 voxel.
struct MeshFairing {
    int passes = 2;           // lambda-then-mu pairs; 0 leaves the mesh as it is
    static constexpr int max_passes = 100;  // far beyond use (two already smooth), within time
    double lambda = 0.5;      // the shrinking step, in (0, 1)
    double pass_band = 0.1;   // k_PB = 1/lambda + 1/mu, in (0, 1)
    void validate() const;    // throws ParameterError naming the bad value
};

// Moves vertices only; the triangles stay as they are.
void fair_mesh(Mesh& mesh, const MeshFairing& fairing = {});

// What keep_points_deep did.
struct DepthGuardReport {
    std::size_t near_vertices = 0;   // vertices nearer than the depth (plus a margin) to a point
    std::size_t moved_vertices = 0;  // vertices lifted, those and their neighbours
    int repair_rounds = 0;           // extra lifts of single triangles that were needed
    std::size_t shallow_points = 0;  // points still shallower than the depth at the end
    std::size_t lone_points = 0;     // points left out: no other point within `lone`
};

// Moves the vertices of a closed, outward-oriented mesh outward along their normals,
// smoothly over two rings of neighbours, until every point that lies inside it is at
// least `depth` from the surface (depth and voxel in world units; the voxel sets the
// margin and the smoothness scale); no triangle is turned over. Points outside the
// mesh, and points with no other point within `lone` (the beads of an undersampled
// scan, which lifting only makes grainier), are left alone.
DepthGuardReport keep_points_deep(Mesh& mesh, const PointCloud& points, double depth, double voxel,
                                  double lone = std::numeric_limits<double>::infinity());
DepthGuardReport keep_points_deep(Mesh& mesh, const PointSet& points, double depth, double voxel,
                                  double lone = std::numeric_limits<double>::infinity());  // makes a PointCloud

// How many of the points lie strictly inside the closed mesh (odd crossing count of a ray).
std::size_t count_points_inside(const Mesh& mesh, const PointSet& points);

// Which solid pieces of a closed, outward mesh to keep: a piece is an outward component
// with the cavities (inward components) inside it, its volume the material between.
struct PieceFilter {
    double min_volume = 0;         // drop pieces of less volume (world units cubed)
    std::size_t keep_largest = 0;  // then keep at most this many, largest first (0: all)
    void validate() const;         // throws ParameterError naming the bad value
    bool keeps_all() const { return min_volume == 0 && keep_largest == 0; }  // drops no piece
};
struct PieceReport {
    std::size_t kept = 0, dropped = 0;
    double dropped_volume = 0;
};
// Removes the pieces the filter rejects, their triangles and the vertices left unused.
PieceReport filter_pieces(Mesh& mesh, const PieceFilter& filter);

}  // namespace snvr
