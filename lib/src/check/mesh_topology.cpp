// Pieces, solids, volume and genus of a mesh whole or in parts (mesh_topology.hpp).
#include "check/mesh_topology.hpp"

#include <algorithm>
#include <limits>

#include "geometry/disjoint_sets.hpp"
#include "geometry/vec3_math.hpp"

namespace snvr::detail {

void PartPieces::append(const PartPieces& other) {
    const auto offset = std::uint32_t(pieces());
    faces.insert(faces.end(), other.faces.begin(), other.faces.end());
    edges.insert(edges.end(), other.edges.begin(), other.edges.end());
    vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
    open.insert(open.end(), other.open.begin(), other.open.end());
    volume.insert(volume.end(), other.volume.begin(), other.volume.end());
    for (std::size_t k = 0; k < other.shared_vertices.size();) {
        const std::uint32_t n = other.shared_vertices[k];
        shared_vertices.push_back(n);
        for (std::uint32_t i = 1; i <= n; ++i) shared_vertices.push_back(other.shared_vertices[k + i] + offset);
        k += n + 1;
    }
    total += other.total;
    finite = finite && other.finite;
}

PartPieces part_pieces(const Mesh& mesh, const MeshAdjacency& a, std::size_t own_triangles, std::size_t own_lo,
                       std::size_t own_hi, const VolumeSum& sum) {
    const auto& T = mesh.triangles;
    const std::size_t nt = T.size();
    PartPieces part;
    // Its pieces: the triangles joined over each edge at its own vertices (there it holds
    // every triangle on the edge), labelled in the order of their first triangle.
    DisjointSets sets(nt);
    for (std::size_t v = own_lo; v < own_hi; ++v)
        for (std::size_t k = a.edge_start[v] + 1; k < a.edge_start[v + 1]; ++k)
            if (upper_end(a.edge_items[k]) == upper_end(a.edge_items[k - 1]))
                sets.unite(std::uint32_t(a.edge_items[k - 1]), std::uint32_t(a.edge_items[k]));
    part.label.assign(nt, kNoPiece);
    std::vector<std::uint32_t> of_root(nt, kNoPiece);
    for (std::size_t t = 0; t < nt; ++t) {
        if (degenerate(T[t])) continue;
        std::uint32_t& l = of_root[sets.find(std::uint32_t(t))];
        if (l == kNoPiece) l = std::uint32_t(part.faces.size()), part.faces.push_back(0);
        part.label[t] = l;
    }
    std::vector<std::uint32_t>().swap(of_root);
    const std::size_t n = part.faces.size();
    part.edges.assign(n, 0);
    part.vertices.assign(n, 0);
    part.open.assign(n, 0);
    part.volume.assign(n, 0);
    for (std::size_t t = 0; t < own_triangles; ++t) {
        const ExactSum six = sum.term(mesh.vertices[T[t][0]], mesh.vertices[T[t][1]], mesh.vertices[T[t][2]], part.finite);
        part.total += six;
        if (part.label[t] == kNoPiece) continue;
        ++part.faces[part.label[t]];
        part.volume[part.label[t]] += six;
    }
    // Each edge at its smaller end, in its triangles' piece; a vertex once in each piece
    // its fan meets.
    std::vector<std::uint32_t> met;
    for (std::size_t v = own_lo; v < own_hi; ++v) {
        const std::uint64_t* first = a.edge_items.data() + a.edge_start[v];
        const std::uint64_t* last = a.edge_items.data() + a.edge_start[v + 1];
        for (const std::uint64_t* run = first; run != last;) {
            const std::uint64_t* end = run + 1;
            while (end != last && upper_end(*end) == upper_end(*run)) ++end;
            const std::uint32_t l = part.label[std::uint32_t(*run)];
            ++part.edges[l];
            if (end - run == 1) part.open[l] = 1;
            run = end;
        }
        const std::uint32_t* fan = a.fan_tri.data() + a.fan_start[v];
        const std::size_t around = a.fan_start[v + 1] - a.fan_start[v];
        if (around == 0) continue;
        const std::uint32_t l = part.label[fan[0]];
        bool one = true;
        for (std::size_t k = 1; k < around && one; ++k) one = part.label[fan[k]] == l;
        if (one) {
            ++part.vertices[l];
            continue;
        }
        met.clear();
        for (std::size_t k = 0; k < around; ++k) met.push_back(part.label[fan[k]]);
        std::sort(met.begin(), met.end());
        met.erase(std::unique(met.begin(), met.end()), met.end());
        part.shared_vertices.push_back(std::uint32_t(met.size()));
        part.shared_vertices.insert(part.shared_vertices.end(), met.begin(), met.end());
    }
    return part;
}

Topology joined_topology(MeshReport counts, const PartPieces& all, const std::vector<std::array<std::uint32_t, 2>>& joined,
                         const VolumeSum& sum) {
    const std::size_t n = all.pieces();
    DisjointSets sets(n);
    for (const auto& j : joined) sets.unite(j[0], j[1]);
    // Every piece's counts at its root.
    std::vector<std::uint64_t> faces(n, 0), edges(n, 0), vertices(n, 0);
    std::vector<std::uint8_t> open(n, 0);
    std::vector<ExactSum> volume(n, 0);
    for (std::size_t l = 0; l < n; ++l) {
        const std::uint32_t r = sets.find(std::uint32_t(l));
        faces[r] += all.faces[l];
        edges[r] += all.edges[l];
        vertices[r] += all.vertices[l];
        open[r] |= all.open[l];
        volume[r] += all.volume[l];
    }
    std::vector<std::uint32_t> roots;
    for (std::size_t k = 0; k < all.shared_vertices.size();) {
        const std::uint32_t m = all.shared_vertices[k];
        roots.clear();
        for (std::uint32_t i = 1; i <= m; ++i) roots.push_back(sets.find(all.shared_vertices[k + i]));
        std::sort(roots.begin(), roots.end());
        roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
        for (std::uint32_t r : roots) ++vertices[r];
        k += m + 1;
    }
    Topology topology;
    topology.report = counts;
    MeshReport& r = topology.report;
    r.components = r.solids = 0;
    for (std::size_t l = 0; l < n; ++l) {
        if (sets.find(std::uint32_t(l)) != l || faces[l] == 0) continue;
        ++r.components;
        r.solids += volume[l] > 0;
        if (open[l]) {
            ++topology.open_components;
            continue;
        }
        const long chi = long(vertices[l]) - long(edges[l]) + long(faces[l]);
        topology.genus += (2 - chi) / 2;
    }
    r.volume = all.finite ? sum.six_volume(all.total) / 6 : std::numeric_limits<double>::quiet_NaN();
    return topology;
}

Topology mesh_topology(const Mesh& mesh, const MeshAdjacency& adjacency) {
    const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
    MeshReport counts = part_counts(mesh, adjacency, nt, 0, nv);
    counts.vertices = nv;
    counts.triangles = nt;
    const Bounds box = bounds(mesh.vertices);
    const VolumeSum sum(box.lo, box.hi);
    return joined_topology(counts, part_pieces(mesh, adjacency, nt, 0, nv, sum), {}, sum);
}

}  // namespace snvr::detail
