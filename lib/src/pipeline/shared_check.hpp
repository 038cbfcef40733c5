// make_shell's check over the processes of a tiled run (tiles.hpp): the walls and the
// points' depths, the most of the check's work, measured by each process for the vertices
// and points in its tiles' cores (the first's own tiles dealt to whoever has the least
// work) from the triangles near them (given by the slabs: check/slab_shares.hpp); what no
// share decides asked of every slab (check/slab_queries.hpp), the topology counted by them
// (check/slab_topology.hpp). Without the surface's figures no process measures the check on
// the whole mesh.
#pragma once
#include <functional>
#include <string>

#include "check/slab_mesh.hpp"
#include "check/walls.hpp"
#include "io/formats.hpp"
#include "pipeline/slab_handover.hpp"
#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// measure_quality (surface) or measure_shell of `mesh`, the same figures, its walls (and
// without the surface's figures, its points' depths) shared with the other processes of
// `on` (each is given its share, empty where it has none); what the others measured goes
// to `facts` (TileFacts::check_walls and on). `meanwhile` runs here once this process has
// measured its own part, before the slabs are asked what no share decides and it takes
// the others' figures: about meanwhile_seconds, which it measures less for.
//
// `slabs`: whether the shell is the slabs' own vertices and triangles in turn, as the
// processes kept them (surface_in_slabs, each rounded as `written_as` holds them), or
// their triangles with vertices moved here since (the depth guard run here on the whole
// surface: each is given its vertices), or neither (a piece dropped, or the surface's
// figures asked: the first's slab is then the whole shell, the others' empty;
// facts.check_topology_slabs says which). Every other process's serve_check hears which
// first.
//
// Where the slabs are the shell's only copy (TileFacts::slabs_kept: `mesh` is the first's
// own slab), `moves` are the first's slab's before it was rounded as written (the others'
// are joined to them, the format's rule checked on them all), and `handover` takes the
// first's slab before `meanwhile` and the others' once the check is measured
// (slab_handover.hpp).
enum class SlabsAre : char { Other = 0, Kept = 1, Moved = 2 };
struct SlabsForCheck {
    SlabsAre are = SlabsAre::Other;
    std::string written_as;
    WrittenMoves moves;
    SlabHandover* handover = nullptr;
};
MeshQuality check_sharing(const Mesh& mesh, const PointCloud& points, const Result& run, bool surface,
                          TileScheduler& on, TileFacts& facts, const SlabsForCheck& slabs,
                          const std::function<void()>& meanwhile = {}, double meanwhile_seconds = 0,
                          const Told& told = nullptr);
struct KeptRange;  // solver/shared_filing.hpp
// At another process: its slab's part of the shell's topology, where the first counts it
// by the slabs (`slab`: surface_in_slabs's), its slab's part of every share of the check,
// then its own share measured (`kept`: its range of the points, or null); where the slabs
// are the shell's only copy, its slab handed to the first's sink after.
void serve_check(TileScheduler& on, Mesh slab, KeptRange* kept);

}  // namespace snvr::detail
