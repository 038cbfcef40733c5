// The surface in slabs over the processes (shared_slabs.hpp).
#include "solver/shared_slabs.hpp"

#include <limits>
#include <utility>

#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"
#include "solver/slab_surface.hpp"

namespace snvr {
namespace {

template <class T>
std::uint64_t bytes_of(const std::vector<T>& v) {
    return v.size() * sizeof(T);
}

// The faces' bricks over a slab's planes: the field's shape, where it lies, its table and bricks.
std::uint64_t give_faces(TileScheduler& on, int to, const FacesPart& part) {
    const Field& f = part.field;
    const bool single = f.precision == Precision::Single;
    const std::vector<std::int64_t> head{f.nx, f.ny, f.nz, part.z, single ? 1 : 0};
    detail::send_array(on, to, head.data(), head.size());
    detail::send_array(on, to, f.brick_table().data(), f.brick_table().size());
    if (single) detail::send_array(on, to, f.stored_f32().data(), f.stored_f32().size());
    else detail::send_array(on, to, f.stored_f64().data(), f.stored_f64().size());
    return bytes_of(head) + bytes_of(f.brick_table()) + (single ? bytes_of(f.stored_f32()) : bytes_of(f.stored_f64()));
}
FacesPart take_faces(TileScheduler& on, int from) {
    std::vector<std::int64_t> head;
    detail::receive_array(on, from, head);
    if (head.size() != 5) throw Error("the faces' bricks from the first process are not whole");
    std::vector<std::uint32_t> table;
    detail::receive_array(on, from, table);
    FacesPart part;
    part.z = int(head[3]);
    const int nx = int(head[0]), ny = int(head[1]), nz = int(head[2]);
    if (head[4]) {
        std::vector<float> stored;
        detail::receive_array(on, from, stored);
        part.field = Field::from_bricks(nx, ny, nz, std::move(table), std::move(stored));
    } else {
        std::vector<double> stored;
        detail::receive_array(on, from, stored);
        part.field = Field::from_bricks(nx, ny, nz, std::move(table), std::move(stored));
    }
    return part;
}

// Whether a piece owns any of the planes a slab is welded from.
bool meets(const detail::MeshPiece& p, const detail::Planes& planes) {
    const int lo = p.region.own_lo[2] + p.region.offset[2], hi = p.region.own_hi[2] + p.region.offset[2];
    return lo < planes.hi && hi > planes.lo;
}

// How many pieces, then each's region and arrays.
std::uint64_t give_pieces(TileScheduler& on, int to, const std::vector<detail::MeshPiece>& pieces,
                          const detail::Planes& planes) {
    std::vector<const detail::MeshPiece*> given;
    for (const detail::MeshPiece& p : pieces)
        if (meets(p, planes)) given.push_back(&p);
    const std::uint64_t count = given.size();
    detail::send_array(on, to, &count, 1);
    std::uint64_t bytes = sizeof count;
    for (const detail::MeshPiece* p : given) {
        detail::send_array(on, to, &p->region, 1);
        detail::send_array(on, to, p->mesh.vertices.data(), p->mesh.vertices.size());
        detail::send_array(on, to, p->vertex_keys.data(), p->vertex_keys.size());
        detail::send_array(on, to, p->vertex_owned.data(), p->vertex_owned.size());
        detail::send_array(on, to, p->mesh.triangles.data(), p->mesh.triangles.size());
        detail::send_array(on, to, p->triangle_keys.data(), p->triangle_keys.size());
        bytes += sizeof p->region + bytes_of(p->mesh.vertices) + bytes_of(p->vertex_keys) + bytes_of(p->vertex_owned) +
                 bytes_of(p->mesh.triangles) + bytes_of(p->triangle_keys);
    }
    return bytes;
}
void take_pieces(TileScheduler& on, int from, std::vector<detail::MeshPiece>& into) {
    std::uint64_t count = 0;
    detail::receive_into(on, from, &count, 1);
    for (std::uint64_t i = 0; i < count; ++i) {
        into.emplace_back();
        detail::MeshPiece& p = into.back();
        detail::receive_into(on, from, &p.region, 1);
        detail::receive_array(on, from, p.mesh.vertices);
        detail::receive_array(on, from, p.vertex_keys);
        detail::receive_array(on, from, p.vertex_owned);
        detail::receive_array(on, from, p.mesh.triangles);
        detail::receive_array(on, from, p.triangle_keys);
        if (p.vertex_keys.size() != p.mesh.vertices.size() || p.vertex_owned.size() != p.mesh.vertices.size() ||
            p.triangle_keys.size() != p.mesh.triangles.size())
            throw Error("a tile's piece of the surface from another process is not whole");
    }
}

}  // namespace

Mesh surface_in_slabs(std::vector<detail::MeshPiece>& pieces, Field faces, const Domain& whole, int core_cells,
                      const MeshFairing& fairing, TileScheduler* on, TileFacts& facts) {
    const int processes = on ? on->processes() : 1, me = on ? on->rank() : 0;
    std::vector<std::uint64_t> by_plane(std::size_t(whole.nz), 0);
    for (const detail::MeshPiece& p : pieces) count_by_plane(p, by_plane);
    if (processes > 1) on->sum(by_plane);
    const SlabPlan plan = plan_slabs(by_plane, processes, slab_ghost_planes(fairing));
    // This slab's pieces: its own tiles' and those the others send.
    std::vector<detail::MeshPiece> here;
    FacesPart faces_here;
    std::uint64_t sent = 0;
    // Pairwise, the lower process sending first, so that no two wait on each other.
    for (int q = 0; q < processes && processes > 1; ++q) {
        if (q == me) continue;
        const auto give = [&] {
            if (me == 0) sent += give_faces(*on, q, faces_for(faces, plan.welded(q)));
            sent += give_pieces(*on, q, pieces, plan.welded(q));
        };
        const auto take = [&] {
            if (q == 0) faces_here = take_faces(*on, q);
            take_pieces(*on, q, here);
        };
        if (me < q) give(), take();
        else take(), give();
    }
    if (me == 0) faces_here = {std::move(faces), 0};
    for (detail::MeshPiece& p : pieces)
        if (meets(p, plan.welded(me))) here.push_back(std::move(p));
    pieces.clear();
    SlabWeld weld = weld_slab(here, faces_here, whole, core_cells, plan, me, fairing);
    faces_here = FacesPart();
    // Where each slab begins in the whole mesh: the slabs' counts, and the bytes sent.
    const std::size_t P = std::size_t(processes);
    std::vector<std::uint64_t> sizes(2 * P + 1, 0);
    sizes[std::size_t(me)] = weld.vertices;
    sizes[P + std::size_t(me)] = weld.triangles;
    sizes[2 * P] = sent;
    if (processes > 1) on->sum(sizes);
    std::uint64_t first = 0, all_vertices = 0, all_triangles = 0;
    for (std::size_t q = 0; q < P; ++q) {
        first += q < std::size_t(me) ? sizes[q] : 0;
        all_vertices += sizes[q];
        all_triangles += sizes[P + q];
    }
    if (all_vertices >= std::numeric_limits<std::uint32_t>::max())
        throw ResourceError("the tiles' surface: more than 2^32 vertices");
    Mesh own = slab_own(std::move(weld), first);
    facts.slabs = processes;
    facts.slab_ghost = plan.ghost;
    // The slabs' own to the first as well.
    facts.slab_bytes = sizes[2 * P] + (all_vertices - sizes[0]) * sizeof(Vec3) +
                       (all_triangles - sizes[P]) * sizeof(std::array<std::uint32_t, 3>);
    if (processes == 1) return own;
    if (me != 0) {
        detail::send_array(*on, 0, own.vertices.data(), own.vertices.size());
        detail::send_array(*on, 0, own.triangles.data(), own.triangles.size());
        return Mesh();
    }
    own.vertices.resize(std::size_t(all_vertices));
    own.triangles.resize(std::size_t(all_triangles));
    std::size_t v = sizes[0], t = sizes[P];
    for (std::size_t q = 1; q < P; ++q) {
        detail::receive_into(*on, int(q), own.vertices.data() + v, std::size_t(sizes[q]));
        detail::receive_into(*on, int(q), own.triangles.data() + t, std::size_t(sizes[P + q]));
        v += sizes[q];
        t += sizes[P + q];
    }
    return own;
}

}  // namespace snvr
