// Where the tiles of a tiled run (Parameters::tile_cells) run. Without a scheduler they
// all run in this process, one after another. A scheduler spreads them over processes
// that all make the same call on the same points (snvr-cl's MPI one, cli/mpi_tiles.cpp):
// each runs the tiles it owns (balanced by the points near them) and sends the results
// to the root (rank 0), which puts the cores together and goes on to mesh; on the other
// processes the call returns once their tiles are sent, without a phase field or a mesh
// (Result::tiles.worker).
#pragma once
#include <cstddef>
#include <vector>

#include "snvr/field.hpp"

namespace snvr {

// One tile's run, as the root needs it.
struct TileResult {
    std::size_t tile = 0;
    Field field;                  // the tile's phase field, on the tile's own grid
    std::vector<double> figures;  // its steps and facts, flattened (tiled_reconstruct.cpp)
};

class TileScheduler {
public:
    virtual ~TileScheduler() = default;
    virtual int processes() const = 0;
    virtual int rank() const = 0;  // 0: the root
    // A worker's result to the root (sent on while the worker goes on: it keeps the
    // result until sent() has waited for the root to take it).
    virtual void send(TileResult result) = 0;
    virtual void sent() = 0;
    // At the root: whether a result has come in, and the next that has (waiting for one).
    virtual bool waiting() = 0;
    virtual TileResult receive() = 0;
    // The elementwise largest of every process's `mine`, on every process.
    virtual std::vector<int> most(const std::vector<int>& mine) = 0;
};

}  // namespace snvr
