// filter_pieces (mesh.hpp): floating debris dropped piece by piece, a piece being an
// outward component with the cavities it holds, so that no cavity is left without its
// solid and no solid loses its cavities.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "geometry/disjoint_sets.hpp"
#include "geometry/vec3_math.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"

namespace snvr {
namespace {

// Six times the signed volume a triangle adds (origin at `o`, for precision far from 0).
double volume6(const Mesh& m, const std::array<std::uint32_t, 3>& t, const Vec3& o) {
    return dot(sub(m.vertices[t[0]], o), cross(sub(m.vertices[t[1]], o), sub(m.vertices[t[2]], o)));
}

// The triangles of the components marked in `take`.
Mesh submesh(const Mesh& m, const std::vector<std::uint32_t>& component, const std::vector<char>& take) {
    Mesh out;
    out.vertices = m.vertices;  // unused ones do not change a ray's crossings
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        if (take[component[t]]) out.triangles.push_back(m.triangles[t]);
    return out;
}

}  // namespace

void PieceFilter::validate() const {
    if (!(min_volume >= 0 && std::isfinite(min_volume)))
        throw ParameterError("the smallest piece's volume (--min-piece-volume) must be zero or a positive finite "
                             "volume, got " + std::to_string(min_volume));
}

PieceReport filter_pieces(Mesh& mesh, const PieceFilter& filter) {
    filter.validate();
    PieceReport report;
    const std::size_t nt = mesh.triangles.size();
    if (nt == 0 || filter.keeps_all()) return report;  // nothing to drop
    // Components: triangles sharing a vertex.
    DisjointSets sets(mesh.vertices.size());
    for (const auto& t : mesh.triangles) {
        sets.unite(t[0], t[1]);
        sets.unite(t[1], t[2]);
    }
    std::vector<std::uint32_t> root_id(mesh.vertices.size(), UINT32_MAX), component(nt);
    std::uint32_t count = 0;
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t r = sets.find(mesh.triangles[t][0]);
        if (root_id[r] == UINT32_MAX) root_id[r] = count++;
        component[t] = root_id[r];
    }
    const Vec3 origin = mesh.vertices[mesh.triangles[0][0]];
    std::vector<double> volume(count, 0);
    std::vector<std::uint32_t> first(count, UINT32_MAX);  // a vertex of each component
    for (std::size_t t = 0; t < nt; ++t) {
        volume[component[t]] += volume6(mesh, mesh.triangles[t], origin) / 6;
        if (first[component[t]] == UINT32_MAX) first[component[t]] = mesh.triangles[t][0];
    }
    // Each cavity (inward component) joins the smallest solid around it.
    std::vector<std::uint32_t> solids;
    for (std::uint32_t c = 0; c < count; ++c)
        if (volume[c] > 0) solids.push_back(c);
    std::vector<std::uint32_t> piece(count);
    std::iota(piece.begin(), piece.end(), 0u);
    std::vector<Mesh> alone(count);  // each solid's own triangles, made when first needed
    for (std::uint32_t c = 0; c < count; ++c) {
        if (volume[c] > 0) continue;
        std::uint32_t best = UINT32_MAX;
        for (std::uint32_t s : solids) {
            if (solids.size() > 1) {
                if (alone[s].triangles.empty()) {
                    std::vector<char> take(count, 0);
                    take[s] = 1;
                    alone[s] = submesh(mesh, component, take);
                }
                if (count_points_inside(alone[s], {mesh.vertices[first[c]]}) == 0) continue;
            }
            if (best == UINT32_MAX || volume[s] < volume[best]) best = s;
        }
        if (best != UINT32_MAX) piece[c] = best;  // a cavity in nothing stays a piece of its own
    }
    std::vector<double> material(count, 0);  // a piece's solid less its cavities
    for (std::uint32_t c = 0; c < count; ++c) material[piece[c]] += volume[c];
    // Which pieces stay: above the smallest volume, then the largest few.
    std::vector<std::uint32_t> pieces;
    for (std::uint32_t c = 0; c < count; ++c)
        if (piece[c] == c) pieces.push_back(c);
    std::stable_sort(pieces.begin(), pieces.end(), [&](std::uint32_t a, std::uint32_t b) { return material[a] > material[b]; });
    std::vector<char> keep(count, 0);
    std::size_t kept = 0;
    for (std::uint32_t p : pieces) {
        const bool stays = material[p] >= filter.min_volume && (filter.keep_largest == 0 || kept < filter.keep_largest);
        keep[p] = stays;
        if (stays) {
            ++kept;
        } else {
            ++report.dropped;
            report.dropped_volume += material[p];
        }
    }
    report.kept = kept;
    if (report.dropped == 0) return report;
    // Drop their triangles, then the vertices nothing uses (indices kept in order).
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (std::size_t t = 0; t < nt; ++t)
        if (keep[piece[component[t]]]) triangles.push_back(mesh.triangles[t]);
    std::vector<std::uint32_t> new_index(mesh.vertices.size(), UINT32_MAX);
    for (const auto& t : triangles)
        for (std::uint32_t v : t) new_index[v] = 0;
    std::vector<Vec3> vertices;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        if (new_index[v] == 0) {
            new_index[v] = std::uint32_t(vertices.size());
            vertices.push_back(mesh.vertices[v]);
        }
    for (auto& t : triangles)
        for (std::uint32_t& v : t) v = new_index[v];
    mesh.vertices = std::move(vertices);
    mesh.triangles = std::move(triangles);
    return report;
}

}  // namespace snvr
