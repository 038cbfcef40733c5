// How a run fits its memory (Parameters::max_memory, else what the machine has free):
// whole, or in tiles of the largest size that fits, or, under a budget, not at all. Decided
// after the plan and before the band's distance, from the bricks the points come near (the
// band's bricks are among them), so that a run that cannot fit stops before its long part.
//
// The model, stage by stage after the decision, in bytes (r: the solver's real, 4 or 8):
// - the solver, whole or the largest tile: kSolverCopies x 512 r a near brick (level 0's
//   four fields and the coarse levels' three on the band's bricks; the distance's two
//   copies come before them), and its grid's tables;
// - the phase field kept for the mesh: 512 r a near brick (a tiled run holds it while its
//   tiles run); where the tiles make the surface (Parameters::whole_field false) only the
//   bricks next to the cores' faces, and the tiles' parts of the surface (40 bytes a
//   triangle) until they are welded;
// - the mesh, its fairing and guard beside the field (90 bytes a triangle), then its check
//   alone (110): about 90 triangles a near brick, the check's frames (72 bytes) for as many of them
//   as the points come near (at most two a point), and a few bytes a point;
// - the whole grid's tables: the mesher's sign bits and the brick tables
//   (DomainPlan::estimated_bytes).
// What the run already holds (the points, filed) is measured, not modelled.
#pragma once
#include <cstddef>

#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

// The tile size chosen (0: whole) and the facts behind it. Throws ResourceError when a
// budget was given and neither the whole run nor any tile size fits it, naming the part
// that does not.
struct MemoryChoice {
    int tile_cells = 0;
    MemoryFacts facts;
};
MemoryChoice fit_memory(const PointCloud& measured, const DomainPlan& plan, const Parameters& params);

}  // namespace snvr
