// The check's far questions asked of the slabs (slab_queries.hpp).
#include "check/slab_queries.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>

#include "geometry/vec3_math.hpp"
#include "mesh/triangle_grid.hpp"
#include "parallel_sizes.hpp"
#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"

namespace snvr::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A slab's nearest triangle to a point: its squared distance, its number in the whole
// mesh, and the point's side of its plane (0: on it, or no triangle).
struct Nearest {
    double d2 = kInf;
    std::uint32_t triangle = TriangleGrid::none;
    std::int32_t side = 0;
    bool before(const Nearest& o) const { return d2 < o.d2 || (d2 == o.d2 && triangle < o.triangle); }
};

}  // namespace

// One slab's own triangles as a mesh of their own: its vertices, then the others' its
// triangles use.
class SlabAnswers::Own {
public:
    explicit Own(const SlabMesh& slabs) : slabs_(slabs) {
        const SlabPart& part = slabs.part();
        mesh_.vertices.assign(part.vertices, part.vertices + part.vertex_count);
        mesh_.vertices.insert(mesh_.vertices.end(), slabs.foreign_at().begin(), slabs.foreign_at().end());
        mesh_.triangles.reserve(part.triangle_count);
        for (std::size_t t = 0; t < part.triangle_count; ++t) {
            const auto& T = part.triangles[t];
            mesh_.triangles.push_back({local(T[0]), local(T[1]), local(T[2])});
        }
        grid_.emplace(mesh_);
    }
    // Vertex v's number here (none where no own triangle uses it): its slot in the slabs.
    std::uint32_t local(std::uint32_t v) const {
        const std::size_t s = slabs_.slot(v);
        return s == SlabMesh::npos ? TriangleGrid::none : std::uint32_t(s);
    }
    std::vector<double> hits(const std::vector<FarWall>& walls, double eps) const {
        std::vector<double> t(walls.size());
#pragma omp parallel for schedule(dynamic, 64) if (std::ptrdiff_t(walls.size()) > kParallelItems)
        for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(walls.size()); ++k) {
            const FarWall& w = walls[std::size_t(k)];
            t[std::size_t(k)] = grid_->first_hit(w.origin, w.dir, eps, local(w.vertex)).t;
        }
        return t;
    }
    std::vector<Nearest> nearest(const std::vector<Vec3>& points) const {
        std::vector<Nearest> out(points.size());
        const std::uint64_t first = slabs_.triangle_starts()[slabs_.rank()];
#pragma omp parallel for schedule(dynamic, 64) if (std::ptrdiff_t(points.size()) > kParallelItems)
        for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(points.size()); ++k) {
            const Vec3& p = points[std::size_t(k)];
            const TriangleGrid::Closest c = grid_->closest(p);
            if (c.triangle == TriangleGrid::none) continue;
            const auto& T = mesh_.triangles[c.triangle];
            out[std::size_t(k)] = {c.dist_sq, std::uint32_t(first + c.triangle),
                                   face_side(p, mesh_.vertices[T[0]], mesh_.vertices[T[1]], mesh_.vertices[T[2]])};
        }
        return out;
    }
    std::vector<std::uint64_t> crossings(const std::vector<Vec3>& points) const {
        std::vector<std::uint64_t> out(points.size());
#pragma omp parallel for schedule(dynamic, 64) if (std::ptrdiff_t(points.size()) > kParallelItems)
        for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(points.size()); ++k) {
            const Vec3& p = points[std::size_t(k)];
            out[std::size_t(k)] = grid_->count_crossings(p, PointDepths::ray_toward(p, slabs_.box()[0], slabs_.box()[1]));
        }
        return out;
    }

private:
    const SlabMesh& slabs_;
    Mesh mesh_;
    std::optional<TriangleGrid> grid_;
};

SlabAnswers::SlabAnswers(const SlabMesh& slabs) : own_(std::make_unique<Own>(slabs)) {}
SlabAnswers::~SlabAnswers() = default;

namespace {

// Each process's questions to every other, each answered here (answer(questions)), and
// the answers to its own from every other, taken in turn (take(answers)).
template <class Question, class Answer, class Answering, class Taking>
void ask_every_other(TileScheduler& on, const std::vector<Question>& mine, const Answering& answer, const Taking& take) {
    const std::size_t P = std::size_t(on.processes());
    std::vector<std::vector<Question>> theirs(P);
    exchange_pairwise(
        on, [&](int q) { send_array(on, q, mine.data(), mine.size()); },
        [&](int q) { receive_array(on, q, theirs[std::size_t(q)]); });
    std::vector<std::vector<Answer>> answers(P);
    for (std::size_t q = 0; q < P; ++q)
        if (q != std::size_t(on.rank())) answers[q] = answer(theirs[q]);
    exchange_pairwise(
        on, [&](int q) { send_array(on, q, answers[std::size_t(q)].data(), answers[std::size_t(q)].size()); },
        [&](int q) {
            std::vector<Answer> got;
            receive_array(on, q, got);
            if (got.size() != mine.size())
                throw Error("the answers of process " + std::to_string(q) + " to the check's far questions are not whole");
            take(got);
        });
}

}  // namespace

FarAnswers ask_slabs(const SlabMesh& slabs, double eps, const FarQuestions& asked, TileScheduler& on,
                     const SlabAnswers* ready) {
    const std::vector<FarWall>& walls = asked.walls;
    const std::vector<Vec3>& points = asked.points;
    std::vector<std::uint64_t> counts{walls.size(), points.size(), asked.sides.size()};
    on.sum(counts);
    FarAnswers out;
    out.hits.assign(walls.size(), kInf);
    out.depths.assign(points.size(), PointDepths::Depth{kInf, false});
    out.inside.assign(asked.sides.size(), 0);
    out.points_asked = counts[1] + counts[2];
    if (counts[0] + counts[1] + counts[2] == 0) return out;
    std::optional<SlabAnswers> made;
    if (!ready) ready = &made.emplace(slabs);
    const SlabAnswers::Own& own = ready->own();
    // The walls: the least hit of any slab.
    if (counts[0]) {
        out.hits = own.hits(walls, eps);
        ask_every_other<FarWall, double>(
            on, walls, [&](const std::vector<FarWall>& w) { return own.hits(w, eps); },
            [&](const std::vector<double>& t) {
                for (std::size_t k = 0; k < t.size(); ++k) out.hits[k] = std::min(out.hits[k], t[k]);
            });
    }
    // The points: the nearest triangle of any slab, and the side of its plane.
    std::vector<Vec3> by_rays = asked.sides;
    std::vector<std::size_t> planar;  // the points on their nearest triangle's plane, after the sides
    if (counts[1]) {
        std::vector<Nearest> nearest = own.nearest(points);
        ask_every_other<Vec3, Nearest>(
            on, points, [&](const std::vector<Vec3>& p) { return own.nearest(p); },
            [&](const std::vector<Nearest>& n) {
                for (std::size_t k = 0; k < n.size(); ++k)
                    if (n[k].before(nearest[k])) nearest[k] = n[k];
            });
        for (std::size_t k = 0; k < points.size(); ++k) {
            out.depths[k] = {std::sqrt(nearest[k].d2), nearest[k].side < 0};
            if (nearest[k].side == 0) {
                by_rays.push_back(points[k]);
                planar.push_back(k);
            }
        }
    }
    // Those by the parity of a ray's crossings, summed over the slabs (each triangle is one
    // slab's own: counted once).
    std::vector<std::uint64_t> rays{by_rays.size()};
    on.sum(rays);
    if (rays[0] == 0) return out;
    std::vector<std::uint64_t> crossings = own.crossings(by_rays);
    ask_every_other<Vec3, std::uint64_t>(
        on, by_rays, [&](const std::vector<Vec3>& p) { return own.crossings(p); },
        [&](const std::vector<std::uint64_t>& c) {
            for (std::size_t k = 0; k < c.size(); ++k) crossings[k] += c[k];
        });
    const std::size_t sides = asked.sides.size();
    for (std::size_t k = 0; k < sides; ++k) out.inside[k] = crossings[k] % 2 == 1;
    for (std::size_t i = 0; i < planar.size(); ++i) out.depths[planar[i]].inside = crossings[sides + i] % 2 == 1;
    return out;
}

}  // namespace snvr::detail
