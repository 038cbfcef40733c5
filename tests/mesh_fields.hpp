// Shared by the isosurface tests: a grid filled from a function of position, and
// the checks every printable mesh must pass.
#pragma once
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"

namespace snvr::testing {

constexpr double kPi = 3.14159265358979323846;

struct Grid {
    Domain domain;
    Field field;
};

template <class F>  // F(position, i, j, k) -> value
Grid make_grid(int nx, int ny, int nz, double h, Vec3 origin, F f, Precision precision = Precision::Double) {
    Grid g;
    g.domain.origin = origin;
    g.domain.h = h;
    g.domain.nx = nx;
    g.domain.ny = ny;
    g.domain.nz = nz;
    std::vector<double> v(g.domain.cells());
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) v[g.domain.index(i, j, k)] = f(g.domain.cell_center(i, j, k), i, j, k);
    g.field = Field::from_dense(nx, ny, nz, v, precision);
    return g;
}

inline double dist(const Vec3& a, const Vec3& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Closed, manifold and consistently oriented, with no degenerate triangles.
inline void check_printable(const MeshReport& r) {
    CHECK(r.boundary_edges == 0);
    CHECK(r.nonmanifold_edges == 0);
    CHECK(r.nonmanifold_vertices == 0);
    CHECK(r.degenerate_triangles == 0);
    CHECK(r.misoriented_edges == 0);
    CHECK(r.closed());
    CHECK(r.manifold());
    CHECK(r.oriented());
}

// `a` with `b` appended, b's vertex numbers moved past a's.
inline Mesh merge(const Mesh& a, const Mesh& b) {
    Mesh m = a;
    const auto off = std::uint32_t(a.vertices.size());
    m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (auto t : b.triangles) m.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
    return m;
}

}  // namespace snvr::testing
