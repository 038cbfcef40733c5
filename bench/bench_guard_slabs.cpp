// bench_guard_slabs CLOUD RESOLUTION SLABS [OFFSET_VOXELS]: whether the depth guard can run
// on slabs of the surface (lib/src/solver/slab_surface.hpp) as the fairing does. The
// surface is welded and faired slab by slab with G ghost planes on either side; each slab
// then runs the guard alone on its mesh and the points within 4 voxels of its planes (in
// the whole tree's frame, so in its order); its own vertices are compared, bit for bit,
// with the guard's on the whole faired mesh. Prints how many differ for G from 4 (the
// fairing's) to 24. An experiment for the mesh stage by process (issue 35), not a timing.
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "geometry/point_tree.hpp"
#include "mesh/dual_pieces.hpp"
#include "mesh/fair_and_keep_deep.hpp"
#include "mesh/vertex_lists.hpp"
#include "snvr/point_io.hpp"
#include "snvr/reconstruct.hpp"
#include "solver/slab_surface.hpp"
#include "solver/tile_plan.hpp"
#include "solver/tile_surface.hpp"

using namespace snvr;

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: bench_guard_slabs CLOUD RESOLUTION SLABS [OFFSET_VOXELS]\n");
        return 1;
    }
    try {
        const PointCloud cloud(read_points(argv[1]));
        Parameters p;
        p.resolution = std::atoi(argv[2]);
        p.device = "openmp";
        const int slabs = std::atoi(argv[3]);
        if (argc > 4) p.offset = std::atof(argv[4]) * reconstruct(cloud, p).domain.h;
        const Result r = reconstruct(cloud, p);
        const Domain& d = r.domain;
        const double depth = r.offset - r.tube_inner, voxel = d.h;
        const double lone = r.offset >= r.gap ? std::numeric_limits<double>::infinity() : r.offset;
        const detail::PointTree& tree = detail::tree_of(cloud);
        const MeshFairing fairing;
        Mesh whole = extract_dual_isosurface(r.phi, d);
        fair_mesh(whole, fairing);
        detail::VertexLists rings, fans;
        detail::rings_and_fans(whole, rings, &fans);
        const DepthGuardReport g = detail::keep_points_deep(whole, tree, depth, voxel, lone, rings, fans);
        std::printf("whole: %zu vertices, %zu moved, %zu near points, %d repair rounds; depth %.3g voxels\n",
                    whole.vertices.size(), g.moved_vertices, g.near_vertices, g.repair_rounds, depth / voxel);
        const int cells = 64;
        const std::vector<Tile> tiles = plan_tiles(d, cells, 8);
        std::vector<detail::MeshPiece> pieces;
        std::vector<std::uint64_t> by_plane(std::size_t(d.nz), 0);
        for (const Tile& t : tiles)
            for (detail::MeshPiece& piece : tile_surface(detail::field_part(r.phi, t.lo, t.hi), t, d, kSlabSlice)) {
                count_by_plane(piece, by_plane);
                pieces.push_back(std::move(piece));
            }
        const FacesPart faces{r.phi, 0};
        for (int ghost : {4, 6, 8, 10, 12, 16, 24}) {
            const SlabPlan plan = plan_slabs(by_plane, slabs, ghost);
            std::size_t first = 0, differ = 0;
            for (int s = 0; s < slabs; ++s) {
                std::vector<detail::MeshPiece> given = pieces;
                SlabWeld w = weld_slab(given, faces, d, cells, plan, s, fairing);
                const detail::Planes planes = plan.welded(s);
                const double reach = 4 * voxel;
                const double lo = d.origin[2] + planes.lo * d.h - reach, hi = d.origin[2] + planes.hi * d.h + reach;
                detail::PointArray<Vec3f> xyz;
                for (std::size_t k = 0; k < tree.size(); ++k)
                    if (const double z = tree.point(k)[2]; z >= lo && z <= hi) xyz.push_back(tree.xyz[k]);
                const PointCloud near = detail::cloud_of(std::move(xyz), tree.origin, &tree.frame());
                detail::VertexLists slab_rings, slab_fans;
                detail::rings_and_fans(w.mesh, slab_rings, &slab_fans);
                detail::keep_points_deep(w.mesh, detail::tree_of(near), depth, voxel, lone, slab_rings, slab_fans);
                for (std::size_t v = 0; v < w.vertices; ++v) differ += w.mesh.vertices[w.below + v] != whole.vertices[first + v];
                first += w.vertices;
            }
            std::printf("%d slabs, %2d ghost planes: %zu of %zu vertices differ\n", slabs, ghost, differ, first);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_guard_slabs: %s\n", e.what());
        return 1;
    }
    return 0;
}
