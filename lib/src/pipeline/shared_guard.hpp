// The depth guard's first search over the processes of a tiled run (tiles.hpp) whose
// points' tree they filed together (solver/shared_filing.hpp): each other process
// searches its own range of the points, kept since the filing, on the faired mesh the
// first gives it, while the first searches its own range; the same vertices and pairs
// as one process finds (mesh/guard_search.hpp).
#pragma once
#include "mesh/guard_search.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

struct KeptRange;  // solver/shared_filing.hpp

// At the first process of a run spread over processes (`on`: null or one process, none).
// Once its mesh stage is over, done() tells every other process whether it searched (once,
// whatever the stage did: each other waits for it, answer_guard_search).
class GuardSearchShared {
public:
    GuardSearchShared(TileScheduler* on, const PointCloud& points, TileFacts& facts);
    // The hook for keep_points_deep; null where the others hold no ranges of these points.
    const GuardElsewhere* elsewhere() const { return hook_.ask ? &hook_ : nullptr; }
    void done();

private:
    TileScheduler* on_;
    GuardElsewhere hook_;
    bool asked_ = false;
};

// At another process, once its tiles are sent: its range's part of the first's search,
// where the first asks it (else nothing).
void answer_guard_search(TileScheduler& on, KeptRange* kept);

}  // namespace snvr::detail
