// What a mesh becomes in its file: float32 formats round every coordinate, which far
// from the origin (survey data) moves vertices by a sizeable part of a voxel; 3MF
// also rounds to six decimals, which matters for a tiny part in large units.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "io/formats.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr {
namespace {

// The share of a voxel by which writing may move a vertex: far below what shows
// (the fairing moves vertices by ~0.1 voxel), and no zero-area triangle comes of it.
constexpr double kLargestMove = 0.01;

using detail::Stores;

// How the format holds a coordinate (formats.cpp): STL and PLY as float32; 3MF (lib3mf
// 1.x) as float32 printed with six decimals; OBJ with every digit.
Stores holds(const std::string& path) {
    const detail::Format* format = detail::format_of(path);
    return format ? format->write.stores : Stores::Exactly;
}

double as_held(double x, Stores how) {
    if (how == Stores::Exactly) return x;
    const double f = double(float(x));
    return how == Stores::Float32 ? f : std::round(f * 1e6) / 1e6;
}

std::string short_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

}  // namespace

Mesh as_written(Mesh mesh, const std::string& path) {
    const Stores how = holds(path);
    if (how == Stores::Exactly) return mesh;
    // Over the coordinates as one array: GCC 12.2 at -O3 vectorises the loop over each
    // vertex's three wrongly, leaving x and y of the last two vertices unrounded where the
    // count is 2 modulo 4 (tests/test_io.cpp holds it).
    double* x = mesh.vertices.empty() ? nullptr : mesh.vertices.front().data();
    for (std::size_t i = 0, n = 3 * mesh.vertices.size(); i < n; ++i) x[i] = as_held(x[i], how);
    return mesh;
}

detail::WrittenMoves detail::written_moves(const Vec3* vertices, std::size_t count, const std::string& path) {
    WrittenMoves moves;
    const Stores how = holds(path);
    if (how == Stores::Exactly) return moves;
    for (std::size_t v = 0; v < count; ++v)
        for (double x : vertices[v]) {
            moves.largest = std::max(moves.largest, std::fabs(x - as_held(x, how)));
            moves.farthest = std::max(moves.farthest, std::fabs(x));
        }
    return moves;
}

void detail::require_written_moves(const WrittenMoves& moves, const std::string& path, double voxel) {
    const Stores how = holds(path);
    if (how == Stores::Exactly || moves.largest <= kLargestMove * voxel) return;
    throw IoError("cannot write '" + path + "' faithfully: the format stores 32-bit floats" +
                     std::string(how == Stores::Float32SixDecimals ? " with six decimals" : "") +
                     ", which at coordinates up to " +
                     short_number(moves.farthest) + " move vertices by up to " +
                     short_number(moves.largest / voxel) + " voxels (" + short_number(moves.largest) +
                     "); nothing written. Write .obj (exact digits), or shift the coordinates to the origin "
                     "(snvr-cl: --origin center)");
}

void require_written_precision(const Mesh& mesh, const std::string& path, double voxel) {
    detail::require_written_moves(detail::written_moves(mesh.vertices.data(), mesh.vertices.size(), path), path, voxel);
}

bool holds_faithfully(double farthest, const std::string& path, double voxel) {
    const Stores how = holds(path);
    if (how == Stores::Exactly) return true;
    // float32 rounds by at most 2^-24 of the coordinate; six decimals by 5e-7 more.
    const double move = std::ldexp(std::fabs(farthest), -24) + (how == Stores::Float32SixDecimals ? 5e-7 : 0.0);
    return move <= kLargestMove * voxel;
}

}  // namespace snvr
