// The paper's Table 2 set-up (cube, sphere, cylinder of size 0.35 in the unit cube,
// l = 0.05, eps = 0.005) and its surface errors, shared by the accuracy test and the
// benchmark.
#pragma once
#include <cmath>
#include <functional>
#include <string>

#include "snvr/shapes.hpp"
#include "snvr/snvr.hpp"

namespace snvr::table2 {

struct Shape {
    std::string name;
    std::function<double(const Vec3&)> distance;  // unsigned, to the exact surface
    std::function<bool(const Vec3&)> inside;
    double paper_grown_128, paper_shrunk_128, paper_grown_256, paper_shrunk_256;
};

inline std::vector<Shape> shapes() {
    const Vec3 c{0.5, 0.5, 0.5};
    const double s = 0.35;
    return {
        {"sphere", [=](const Vec3& p) { return shapes::sphere_distance(p, c, s); },
         [=](const Vec3& p) { return std::hypot(p[0] - c[0], p[1] - c[1], p[2] - c[2]) < s; }, 1.804e-3, 2.013e-3,
         4.523e-4, 5.243e-4},
        {"cube", [=](const Vec3& p) { return shapes::cube_distance(p, c, s); },
         [=](const Vec3& p) {
             return std::abs(p[0] - c[0]) < s / 2 && std::abs(p[1] - c[1]) < s / 2 && std::abs(p[2] - c[2]) < s / 2;
         },
         5.652e-3, 6.416e-3, 1.565e-3, 1.747e-3},
        {"cylinder", [=](const Vec3& p) { return shapes::cylinder_distance(p, c, s, s); },
         [=](const Vec3& p) { return std::hypot(p[0] - c[0], p[1] - c[1]) < s && std::abs(p[2] - c[2]) < s / 2; },
         2.264e-3, 2.987e-3, 5.861e-4, 7.581e-4},
    };
}

// steps < 0: the default flow (Parameters::smoothing_cells in steps of dt_cells).
inline Parameters parameters(int resolution, int steps = -1) {
    Parameters p;
    p.box = std::array<Vec3, 2>{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
    p.resolution = resolution;
    p.offset = 0.05;
    p.eps = 0.005;
    if (steps >= 0) p.steps = steps;
    return p;
}

struct Errors {
    double grown = 0, shrunk = 0;  // RMS of (distance to the exact surface - l) over each sheet's vertices
    std::size_t grown_vertices = 0, shrunk_vertices = 0;
};

inline Errors surface_errors(const Mesh& mesh, const Shape& shape, double offset) {
    Errors e;
    for (const Vec3& v : mesh.vertices) {
        const double err = shape.distance(v) - offset;
        if (shape.inside(v)) {
            e.shrunk += err * err;
            ++e.shrunk_vertices;
        } else {
            e.grown += err * err;
            ++e.grown_vertices;
        }
    }
    e.grown = std::sqrt(e.grown / double(std::max<std::size_t>(1, e.grown_vertices)));
    e.shrunk = std::sqrt(e.shrunk / double(std::max<std::size_t>(1, e.shrunk_vertices)));
    return e;
}

}  // namespace snvr::table2
