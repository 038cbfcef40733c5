// What no process's share of the check can decide, asked of every slab of the mesh
// (slab_mesh.hpp): a wall whose first hit lies beyond its share's reach (where its ray
// first meets the mesh), a point whose nearest triangle lies beyond it or whose side only
// a ray's crossings tell. Each slab answers over its own triangles; the least hit, the
// nearest triangle (of several at one distance the lowest numbered, as
// TriangleGrid::closest takes it) and its side, and the crossings summed are the whole
// mesh's, to the bit, so that no process needs the whole mesh for them.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "check/point_depths.hpp"
#include "check/slab_mesh.hpp"
#include "snvr/geometry.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// A wall's ray: from the vertex (the whole mesh's number, whose own triangles it passes)
// along its inward normal.
struct FarWall {
    Vec3 origin{0, 0, 0}, dir{0, 0, 0};
    std::uint32_t vertex = 0;
};

// A process's questions: walls, points (their nearest triangle and side), and points
// whose nearest triangle its share found but whose side only a ray's crossings tell.
struct FarQuestions {
    std::vector<FarWall> walls;
    std::vector<Vec3> points, sides;
};
// The answers: each wall's first hit beyond eps (infinity: none), each point's depth as
// PointDepths measures it on the whole mesh (the side of its nearest triangle's plane
// where its foot lies clear inside it, else a ray's crossings), and each of `sides`
// whether it lies inside; and the points all processes asked.
struct FarAnswers {
    std::vector<double> hits;
    std::vector<PointDepths::Depth> depths;
    std::vector<std::uint8_t> inside;
    std::uint64_t points_asked = 0;
};

// This slab's own triangles made ready to answer (a grid over them), where a process has
// the time before it asks (made in ask_slabs otherwise). The slabs are kept meanwhile.
class SlabAnswers {
public:
    explicit SlabAnswers(const SlabMesh& slabs);
    ~SlabAnswers();
    class Own;  // slab_queries.cpp
    const Own& own() const { return *own_; }

private:
    std::unique_ptr<Own> own_;
};

// Every process at once, each with its own questions; `ready`: this slab's answers made
// already (null: made here, and not where no process asks anything).
FarAnswers ask_slabs(const SlabMesh& slabs, double eps, const FarQuestions& asked, TileScheduler& on,
                     const SlabAnswers* ready = nullptr);

}  // namespace snvr::detail
