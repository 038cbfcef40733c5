// snvr-cl's processes: one, or those an MPI launcher (mpirun, srun) started, where
// snvr-cl was built with MPI (processes_mpi.cpp; else processes_single.cpp). Under MPI
// the processes share a tiled run's tiles (--tile-cells): each runs its own, the first
// (rank 0) meshes, checks, writes and reports; the others stay quiet.
#pragma once
#include <memory>
#include <string>

#include "snvr/tiles.hpp"

namespace cli {

// The size of the job a launcher says this process is part of (OpenMPI, MPICH and
// Slurm's PMI set these), or 1 for a process started alone.
int launched_size();

// Starts MPI where a launcher started this process (before anything else in main; a
// process started alone does without: MPI's own start costs 0.4 s). Where snvr-cl was
// built without MPI and a launcher started several copies, throws snvr::Error: they
// would all write one output.
void start_processes(int& argc, char**& argv);
// Ends MPI; `failed`: this process failed, so the others are stopped too.
void end_processes(bool failed);
int process_count();
int process_rank();
// The processes as a tiled run's scheduler; null for one process.
std::shared_ptr<snvr::TileScheduler> process_tiles();

}  // namespace cli
