// The depth guard a run's plan asks for (make_shell's: the mesher's, or the slabs' where
// the tiles make the surface over several processes, solver/shared_slabs.hpp).
#pragma once
#include "mesh/fair_and_keep_deep.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr::detail {

// The depth of the tube's inner wall, and lone at the offset where the offset is below the
// sampling gap. The tube's inner wall is the depth promised. Where the offset is below the
// points' spacing the shell is a chain of beads around single points; lifting each bead's
// top made it grainier (undersampled torus: 8.1 -> 8.8 deg dihedral), so those points are
// left out, unless the offset reaches the sampling gap (then the promise covers every
// point). Whether there is a guard at all: has_inner_wall.
KeepDeep keep_deep_of(const DomainPlan& plan);
inline bool has_inner_wall(const DomainPlan& plan) { return plan.tube_inner > 0; }

}  // namespace snvr::detail
