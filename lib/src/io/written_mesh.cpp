// What a mesh becomes in its file: float32 formats round every coordinate, which far
// from the origin (survey data) moves vertices by a sizeable part of a voxel.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "io/io_common.hpp"
#include "snvr/error.hpp"
#include "snvr/io.hpp"

namespace snvr {
namespace {

// The share of a voxel by which writing may move a vertex: far below what shows
// (the fairing moves vertices by ~0.1 voxel), and no zero-area triangle comes of it.
constexpr double kLargestMove = 0.01;

bool stores_float32(const std::string& path) {
    const std::string ext = detail::lower_extension(path);
    return ext == ".stl" || ext == ".ply";
}

std::string short_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

}  // namespace

Mesh as_written(const Mesh& mesh, const std::string& path) {
    Mesh out = mesh;
    if (stores_float32(path))
        for (Vec3& v : out.vertices)
            for (double& x : v) x = double(float(x));
    return out;
}

void require_written_precision(const Mesh& mesh, const std::string& path, double voxel) {
    if (!stores_float32(path)) return;
    double largest = 0, farthest = 0;
    for (const Vec3& v : mesh.vertices)
        for (double x : v) {
            largest = std::max(largest, std::fabs(x - double(float(x))));
            farthest = std::max(farthest, std::fabs(x));
        }
    if (largest <= kLargestMove * voxel) return;
    throw InputError(path + ": the format stores 32-bit floats, which at coordinates up to " +
                     short_number(farthest) + " move vertices by up to " +
                     short_number(largest / voxel) + " voxels (" + short_number(largest) +
                     "); nothing written. Write .obj (exact digits), or shift the coordinates to the origin "
                     "(snvr-cl: --origin center)");
}

}  // namespace snvr
