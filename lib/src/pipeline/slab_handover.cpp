// The shell handed on slab by slab (slab_handover.hpp).
#include "pipeline/slab_handover.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/stopwatch.hpp"
#include "solver/sent_arrays.hpp"

namespace snvr::detail {
namespace {

// A run of 2^20 triangles (12 MB, and the vertices they use) or vertices (24 MB) at a time:
// the first holds its own slab and one run.
constexpr std::size_t kHandoverRun = std::size_t(1) << 20;

using Triangle = std::array<std::uint32_t, 3>;

// Slab q's runs of `count` things, in turn.
template <class Each>
void by_runs(std::uint64_t count, const Each& each) {
    for (std::uint64_t at = 0; at < count; at += kHandoverRun) each(at, std::min<std::uint64_t>(kHandoverRun, count - at));
}

// At another process: its triangles from `at`, `n` of them, and where the sink wants
// corners the window of its own vertices they use (its first number, then the window).
void send_triangles(TileScheduler& on, const SlabPart& part, std::uint64_t first_vertex, std::uint64_t at,
                    std::uint64_t n, bool corners) {
    const Triangle* t = part.triangles + at;
    if (corners) {
        std::uint64_t lo = first_vertex + part.vertex_count, hi = first_vertex;
        for (std::uint64_t k = 0; k < n; ++k)
            for (std::uint32_t v : t[k])
                if (v >= first_vertex && v < first_vertex + part.vertex_count) {
                    lo = std::min<std::uint64_t>(lo, v);
                    hi = std::max<std::uint64_t>(hi, v + 1);
                }
        if (lo > hi) lo = hi;
        send_array(on, 0, &lo, 1);
        send_array(on, 0, part.vertices + (lo - first_vertex), hi - lo);
    }
    send_array(on, 0, t, n);
}

// Its own slab as a part: its vertices and triangles, and the others' vertices they use.
MeshPart own_part(const SlabMesh& slabs) {
    const SlabPart& part = slabs.part();
    MeshPart own;
    own.first_vertex = slabs.starts()[slabs.rank()];
    own.vertices = part.vertices;
    own.vertex_count = part.vertex_count;
    own.triangles = part.triangles;
    own.triangle_count = part.triangle_count;
    own.foreign = slabs.foreign().data();
    own.foreign_at = slabs.foreign_at().data();
    own.foreign_count = slabs.foreign().size();
    return own;
}

}  // namespace

void give_slab(const SlabMesh& slabs, TileScheduler& on) {
    const SlabPart& part = slabs.part();
    std::uint8_t corners = 0;
    receive_into(on, 0, &corners, 1);
    const std::uint64_t first = slabs.starts()[slabs.rank()];
    if (corners) {
        send_array(on, 0, slabs.foreign().data(), slabs.foreign().size());
        send_array(on, 0, slabs.foreign_at().data(), slabs.foreign_at().size());
    } else {
        by_runs(part.vertex_count, [&](std::uint64_t at, std::uint64_t n) { send_array(on, 0, part.vertices + at, n); });
    }
    by_runs(part.triangle_count, [&](std::uint64_t at, std::uint64_t n) { send_triangles(on, part, first, at, n, corners); });
}

void SlabHandover::own(const SlabMesh& slabs) {
    if (begun_) return;
    Stopwatch clock;
    begun_ = true;
    box_ = slabs.box();
    sink_.begin(slabs.starts().back(), slabs.triangle_starts().back());
    const MeshPart part = own_part(slabs);
    if (sink_.wants_corners()) sink_.triangles(part);
    else sink_.vertices(part);
    seconds_ += clock.lap();
}

void SlabHandover::rest(const SlabMesh& slabs) {
    own(slabs);
    Stopwatch clock;
    const std::size_t P = slabs.processes();
    const std::vector<std::uint64_t>& starts = slabs.starts();
    const std::vector<std::uint64_t>& triangle_starts = slabs.triangle_starts();
    const std::uint8_t corners = sink_.wants_corners();
    for (std::size_t q = 1; q < P; ++q) send_array(on_, int(q), &corners, 1);
    std::vector<Vec3> vertices;
    std::vector<Triangle> triangles;
    if (!corners) {
        for (std::size_t q = 1; q < P; ++q)
            by_runs(starts[q + 1] - starts[q], [&](std::uint64_t at, std::uint64_t n) {
                vertices.resize(n);
                receive_into(on_, int(q), vertices.data(), n);
                MeshPart run;
                run.first_vertex = starts[q] + at;
                run.vertices = vertices.data();
                run.vertex_count = n;
                sink_.vertices(run);
            });
        sink_.triangles(own_part(slabs));
    }
    for (std::size_t q = 1; q < P; ++q) {
        std::vector<std::uint32_t> foreign;
        std::vector<Vec3> foreign_at;
        if (corners) {
            receive_array(on_, int(q), foreign);
            receive_array(on_, int(q), foreign_at);
            if (foreign.size() != foreign_at.size()) throw Error("a slab's foreign vertices from another process are not whole");
        }
        by_runs(triangle_starts[q + 1] - triangle_starts[q], [&](std::uint64_t, std::uint64_t n) {
            MeshPart run;
            if (corners) {
                receive_into(on_, int(q), &run.first_vertex, 1);
                receive_array(on_, int(q), vertices);
                run.vertices = vertices.data();
                run.vertex_count = vertices.size();
                run.foreign = foreign.data();
                run.foreign_at = foreign_at.data();
                run.foreign_count = foreign.size();
            }
            triangles.resize(n);
            receive_into(on_, int(q), triangles.data(), n);
            run.triangles = triangles.data();
            run.triangle_count = n;
            sink_.triangles(run);
        });
    }
    sink_.finish();
    seconds_ += clock.lap();
}

}  // namespace snvr::detail
