// preview_png (snvr/render.hpp): the shell as a user checks it before printing, the
// outside shaded and a cut through its middle.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/vec3_math.hpp"
#include "snvr/render.hpp"

namespace snvr::render {
namespace {

// A cut through the mesh at y = level, seen from +y (x right, z down), filled by the
// even-odd rule: a closed mesh cut by a plane gives closed loops, and a pixel inside
// an odd number of them is material. A vertex on the plane counts as above it, so
// every loop closes.
std::vector<std::uint8_t> cross_section(const Mesh& mesh, int size) {
    std::vector<std::uint8_t> rgb(std::size_t(size) * size * 3, 255);
    if (mesh.vertices.empty()) return rgb;
    const auto [lo, hi] = bounds(mesh.vertices);
    const double level = 0.5 * (lo[1] + hi[1]);
    // The panel shows the box's x and z at one scale, with the shaded view's 4% margin.
    const double extent = std::max({hi[0] - lo[0], hi[2] - lo[2], 1e-300}) * 1.04;
    const double scale = size / extent, cx = 0.5 * (lo[0] + hi[0]), cz = 0.5 * (lo[2] + hi[2]);
    struct Segment {
        double x0, z0, x1, z1;  // pixels
    };
    std::vector<std::vector<double>> crossings(static_cast<std::size_t>(size));
    for (const auto& t : mesh.triangles) {
        std::array<double, 2> ends[2];
        int found = 0;
        for (int e = 0; e < 3 && found < 2; ++e) {
            const Vec3 &p = mesh.vertices[t[e]], &q = mesh.vertices[t[(e + 1) % 3]];
            const bool above_p = p[1] >= level, above_q = q[1] >= level;
            if (above_p == above_q) continue;
            const double s = (level - p[1]) / (q[1] - p[1]);
            ends[found++] = {(p[0] + s * (q[0] - p[0]) - cx) * scale + 0.5 * size,
                             (p[2] + s * (q[2] - p[2]) - cz) * scale + 0.5 * size};
        }
        if (found < 2) continue;
        const Segment g{ends[0][0], ends[0][1], ends[1][0], ends[1][1]};
        // Rows whose centre z + 0.5 lies in [z0, z1): each crossing counted once.
        const double z0 = std::min(g.z0, g.z1), z1 = std::max(g.z0, g.z1);
        const int r0 = std::max(0, int(std::ceil(z0 - 0.5))), r1 = std::min(size - 1, int(std::ceil(z1 - 0.5)) - 1);
        for (int r = r0; r <= r1; ++r) {
            const double z = r + 0.5, s = (z - g.z0) / (g.z1 - g.z0);
            crossings[std::size_t(r)].push_back(g.x0 + s * (g.x1 - g.x0));
        }
    }
    for (int r = 0; r < size; ++r) {
        std::vector<double>& xs = crossings[std::size_t(r)];
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
            const int c0 = std::max(0, int(std::ceil(xs[k] - 0.5))), c1 = std::min(size - 1, int(std::ceil(xs[k + 1] - 0.5)) - 1);
            for (int c = c0; c <= c1; ++c)
                for (int ch = 0; ch < 3; ++ch) rgb[(std::size_t(r) * size + c) * 3 + ch] = ch == 2 ? 90 : 60;
        }
    }
    return rgb;
}

}  // namespace

std::string preview_png(const Mesh& mesh, const std::string& path, int size) {
    RenderView view;
    view.width = view.height = size;
    const std::vector<std::uint8_t> left = render_rgb(mesh, view), right = cross_section(mesh, size);
    // Side by side, a grey rule between them.
    const int width = 2 * size + 4;
    std::vector<std::uint8_t> rgb(std::size_t(width) * size * 3, 170);
    for (int r = 0; r < size; ++r) {
        std::copy_n(&left[std::size_t(r) * size * 3], std::size_t(size) * 3, &rgb[std::size_t(r) * width * 3]);
        std::copy_n(&right[std::size_t(r) * size * 3], std::size_t(size) * 3, &rgb[(std::size_t(r) * width + size + 4) * 3]);
    }
    return encode_png(rgb, width, size, path);
}

}  // namespace snvr::render
