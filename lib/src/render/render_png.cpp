// Z-buffer rasterizer for mesh previews. Vertices are projected once, snapped to a
// fixed-point sub-pixel grid and every pixel centre is tested against exact integer
// edge functions with a tie rule, so triangles sharing an edge leave neither gaps
// nor double hits, whatever the mesh size.
#include "snvr/render.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "snvr/error.hpp"

namespace snvr::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSubpixelBits = 8;
constexpr double kSubpixel = double(1 << kSubpixelBits);
constexpr double kMargin = 1.04;  // empty border around the mesh in the full view
// Farther than this many pixels outside the image a triangle is dropped; it keeps
// the fixed-point products far inside 64 bits.
constexpr double kFarPixels = 1e6;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
Vec3 scaled(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }

struct Camera {
    Vec3 x, y, z;         // right, up, towards the viewer
    Vec3 target;          // centre of the bounding box
    double distance = 0;  // perspective: from the target to the eye; 0 for orthographic
};

Camera make_camera(const Mesh& mesh, const RenderView& view) {
    Vec3 lo = mesh.vertices.empty() ? Vec3{0, 0, 0} : mesh.vertices[0], hi = lo;
    for (const Vec3& v : mesh.vertices)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
    Camera cam;
    cam.target = scaled({lo[0] + hi[0], lo[1] + hi[1], lo[2] + hi[2]}, 0.5);
    cam.z = scaled(view.direction, 1 / norm(view.direction));
    const Vec3 x = cross(view.up, cam.z);
    if (!(norm(x) > 1e-9 * norm(view.up))) throw ParameterError("render_png: view direction parallel to 'up'");
    cam.x = scaled(x, 1 / norm(x));
    cam.y = cross(cam.z, cam.x);
    if (view.perspective_degrees > 0) {
        // The bounding sphere just fills the field of view: the eye is outside it, so
        // every vertex lies in front of the camera.
        const double radius = std::max(0.5 * norm(sub(hi, lo)), 1e-300);
        cam.distance = radius / std::sin(0.5 * view.perspective_degrees * kPi / 180);
    }
    return cam;
}

void check_view(const RenderView& view) {
    const auto finite3 = [](const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
    if (view.width < 1 || view.height < 1 || view.width > 16384 || view.height > 16384)
        throw ParameterError("render_png: image size must be 1..16384 pixels per side");
    if (!finite3(view.direction) || !(norm(view.direction) > 0)) throw ParameterError("render_png: bad view direction");
    if (!finite3(view.up) || !(norm(view.up) > 0)) throw ParameterError("render_png: bad 'up' direction");
    if (!(view.zoom > 0 && view.zoom <= 1000)) throw ParameterError("render_png: zoom must be in (0, 1000]");
    if (!std::isfinite(view.center[0]) || !std::isfinite(view.center[1]))
        throw ParameterError("render_png: bad zoom centre");
    if (!(view.perspective_degrees >= 0 && view.perspective_degrees < 170))
        throw ParameterError("render_png: perspective must be 0 (orthographic) or a field of view below 170 degrees");
}

// A vertex on screen: pixel coordinates (y down) and a depth key that grows towards
// the viewer and is linear in screen space (view depth, or 1/w in perspective).
struct ScreenVertex {
    double px, py, depth;
};

std::vector<ScreenVertex> project(const Mesh& mesh, const Camera& cam, const RenderView& view) {
    std::vector<ScreenVertex> s(mesh.vertices.size());
    double lo[2] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
    double hi[2] = {-lo[0], -lo[1]};
    for (std::size_t i = 0; i < s.size(); ++i) {
        const Vec3 d = sub(mesh.vertices[i], cam.target);
        double u = dot(d, cam.x), v = dot(d, cam.y), depth = dot(d, cam.z);
        if (cam.distance > 0) {
            const double w = cam.distance - depth;  // > 0: the eye is outside the bounding sphere
            u *= cam.distance / w, v *= cam.distance / w, depth = 1 / w;
        }
        s[i] = {u, v, depth};
        lo[0] = std::min(lo[0], u), hi[0] = std::max(hi[0], u);
        lo[1] = std::min(lo[1], v), hi[1] = std::max(hi[1], v);
    }
    if (s.empty()) return s;
    // Fit the full view, then crop it: pixel = (full-view pixel - crop centre) * zoom + image centre.
    const double W = view.width, H = view.height;
    const double extent_u = std::max(hi[0] - lo[0], 1e-300), extent_v = std::max(hi[1] - lo[1], 1e-300);
    const double scale = std::min(W / extent_u, H / extent_v) / kMargin;
    const double mid_u = 0.5 * (lo[0] + hi[0]), mid_v = 0.5 * (lo[1] + hi[1]);
    for (auto& p : s) {
        const double full_x = 0.5 * W + (p.px - mid_u) * scale, full_y = 0.5 * H - (p.py - mid_v) * scale;
        p.px = (full_x - view.center[0] * W) * view.zoom + 0.5 * W;
        p.py = (full_y - view.center[1] * H) * view.zoom + 0.5 * H;
    }
    return s;
}

// Grey material lit from the camera; back faces tinted red.
struct Shade {
    float r, g, b;
};
Shade shade(double cos_view, bool front) {
    const double c = std::clamp(cos_view, 0.0, 1.0);
    const double diffuse = 0.14 + 0.76 * c, specular = 0.18 * std::pow(c, 40);
    const double base[2][3] = {{0.85, 0.38, 0.32}, {0.80, 0.80, 0.80}};
    const double* m = base[front ? 1 : 0];
    return {float(m[0] * diffuse + specular), float(m[1] * diffuse + specular), float(m[2] * diffuse + specular)};
}

class Rasterizer {
public:
    Rasterizer(int width, int height)
        : w_(width), h_(height), depth_(std::size_t(width) * height, -std::numeric_limits<double>::infinity()),
          color_(std::size_t(width) * height, Shade{1, 1, 1}) {}

    // Fills the pixels whose centres the triangle covers, nearer than what is there,
    // with the colour interpolated from the corners' shades.
    void triangle(const ScreenVertex* v[3], const Shade c[3]) {
        for (int k = 0; k < 3; ++k)
            if (!(std::abs(v[k]->px) < kFarPixels && std::abs(v[k]->py) < kFarPixels)) return;
        std::int64_t x[3], y[3];
        for (int k = 0; k < 3; ++k) x[k] = std::llround(v[k]->px * kSubpixel), y[k] = std::llround(v[k]->py * kSubpixel);
        std::int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
        if (area == 0) return;
        int order[3] = {0, 1, 2};
        if (area < 0) std::swap(order[1], order[2]), area = -area;
        const std::int64_t X[3] = {x[order[0]], x[order[1]], x[order[2]]};
        const std::int64_t Y[3] = {y[order[0]], y[order[1]], y[order[2]]};
        const std::int64_t half = std::int64_t(1) << (kSubpixelBits - 1);
        const auto to_pixel = [](std::int64_t fixed) { return int(fixed >> kSubpixelBits); };
        const int x0 = std::max(0, to_pixel(std::min({X[0], X[1], X[2]}) - half));
        const int x1 = std::min(w_ - 1, to_pixel(std::max({X[0], X[1], X[2]}) - half) + 1);
        const int y0 = std::max(0, to_pixel(std::min({Y[0], Y[1], Y[2]}) - half));
        const int y1 = std::min(h_ - 1, to_pixel(std::max({Y[0], Y[1], Y[2]}) - half) + 1);
        if (x0 > x1 || y0 > y1) return;
        // Edge k runs from corner k+1 to k+2 and is zero on it; its weight is that of corner k.
        // A pixel centre exactly on an edge goes to one side only: the same edge seen
        // from the neighbouring triangle runs the other way and gets the other answer.
        std::int64_t bias[3];
        for (int k = 0; k < 3; ++k) {
            const int a = (k + 1) % 3, b = (k + 2) % 3;
            const std::int64_t dx = X[b] - X[a], dy = Y[b] - Y[a];
            bias[k] = (dy < 0 || (dy == 0 && dx > 0)) ? 0 : -1;
        }
        const double depth[3] = {v[order[0]]->depth, v[order[1]]->depth, v[order[2]]->depth};
        const Shade* shade[3] = {&c[order[0]], &c[order[1]], &c[order[2]]};
        const double inv_area = 1.0 / double(area);
        for (int py = y0; py <= y1; ++py) {
            const std::int64_t sy = (std::int64_t(py) << kSubpixelBits) + half;
            for (int px = x0; px <= x1; ++px) {
                const std::int64_t sx = (std::int64_t(px) << kSubpixelBits) + half;
                std::int64_t e[3];
                bool inside = true;
                for (int k = 0; k < 3 && inside; ++k) {
                    const int a = (k + 1) % 3, b = (k + 2) % 3;
                    e[k] = (X[b] - X[a]) * (sy - Y[a]) - (Y[b] - Y[a]) * (sx - X[a]);
                    inside = e[k] + bias[k] >= 0;
                }
                if (!inside) continue;
                const double l0 = double(e[0]) * inv_area, l1 = double(e[1]) * inv_area, l2 = 1 - l0 - l1;
                const double z = l0 * depth[0] + l1 * depth[1] + l2 * depth[2];
                const std::size_t i = std::size_t(py) * w_ + px;
                if (!(z > depth_[i])) continue;
                depth_[i] = z;
                color_[i] = {float(l0 * shade[0]->r + l1 * shade[1]->r + l2 * shade[2]->r),
                             float(l0 * shade[0]->g + l1 * shade[1]->g + l2 * shade[2]->g),
                             float(l0 * shade[0]->b + l1 * shade[1]->b + l2 * shade[2]->b)};
            }
        }
    }

    std::vector<std::uint8_t> rgb() const {
        std::vector<std::uint8_t> out(color_.size() * 3);
        const auto byte = [](float c) { return std::uint8_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255)); };
        for (std::size_t i = 0; i < color_.size(); ++i)
            out[3 * i] = byte(color_[i].r), out[3 * i + 1] = byte(color_[i].g), out[3 * i + 2] = byte(color_[i].b);
        return out;
    }

private:
    int w_, h_;
    std::vector<double> depth_;
    std::vector<Shade> color_;
};

}  // namespace

std::string encode_png(const std::vector<std::uint8_t>& rgb, int width, int height, const std::string& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = png_uint_32(width);
    image.height = png_uint_32(height);
    image.format = PNG_FORMAT_RGB;
    png_alloc_size_t size = 0;  // first call: how many bytes the encoded image needs
    if (!png_image_write_to_memory(&image, nullptr, &size, 0, rgb.data(), 0, nullptr))
        throw IoError("cannot encode PNG for '" + path + "': " + image.message);
    std::string bytes(size, '\0');
    if (!png_image_write_to_memory(&image, bytes.data(), &size, 0, rgb.data(), 0, nullptr))
        throw IoError("cannot encode PNG for '" + path + "': " + image.message);
    bytes.resize(size);
    return bytes;
}

std::vector<std::uint8_t> render_rgb(const Mesh& mesh, const RenderView& view) {
    check_view(view);
    for (const auto& t : mesh.triangles)
        for (const auto i : t)
            if (i >= mesh.vertices.size()) throw InputError("render_png: triangle refers to a missing vertex");
    const Camera cam = make_camera(mesh, view);
    const std::vector<ScreenVertex> screen = project(mesh, cam, view);
    const Vec3 eye = scaled(cam.z, cam.distance);  // relative to the target, perspective only
    const auto towards_eye = [&](const Vec3& p) {
        if (cam.distance == 0) return cam.z;
        const Vec3 d = sub(eye, sub(p, cam.target));
        return scaled(d, 1 / norm(d));
    };

    // Gouraud only: area-weighted vertex normals (unnormalised cross products summed).
    std::vector<Vec3> vertex_normal;
    if (view.smooth) {
        vertex_normal.assign(mesh.vertices.size(), Vec3{0, 0, 0});
        for (const auto& t : mesh.triangles) {
            const Vec3 n = cross(sub(mesh.vertices[t[1]], mesh.vertices[t[0]]), sub(mesh.vertices[t[2]], mesh.vertices[t[0]]));
            for (const auto i : t)
                for (int a = 0; a < 3; ++a) vertex_normal[i][a] += n[a];
        }
    }

    Rasterizer raster(view.width, view.height);
    for (const auto& t : mesh.triangles) {
        const Vec3& a = mesh.vertices[t[0]];
        const Vec3 n = cross(sub(mesh.vertices[t[1]], a), sub(mesh.vertices[t[2]], a));
        const double length = norm(n);
        if (!(length > 0)) continue;
        Vec3 centroid{0, 0, 0};
        for (const auto i : t)
            for (int k = 0; k < 3; ++k) centroid[k] += mesh.vertices[i][k] / 3;
        const double facing = dot(n, towards_eye(centroid)) / length;
        const bool front = facing > 0;
        Shade c[3];
        for (int k = 0; k < 3; ++k) {
            double cos_view = std::abs(facing);
            if (view.smooth) {
                const Vec3& vn = vertex_normal[t[k]];
                const double vl = norm(vn);
                if (vl > 0) cos_view = (front ? 1 : -1) * dot(vn, towards_eye(mesh.vertices[t[k]])) / vl;
            }
            c[k] = shade(cos_view, front);
        }
        const ScreenVertex* v[3] = {&screen[t[0]], &screen[t[1]], &screen[t[2]]};
        raster.triangle(v, c);
    }
    return raster.rgb();
}

void render_png(const Mesh& mesh, const std::string& path, const RenderView& view) {
    const std::string bytes = encode_png(render_rgb(mesh, view), view.width, view.height, path);
    AtomicFile file(path);
    file.write(bytes);
    file.commit();
}

}  // namespace snvr::render
