// Software previews of meshes as PNG: a z-buffer rasterizer with flat shading by
// default, so that faceting and grid-aligned terraces stay visible.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "snvr/geometry.hpp"

namespace snvr::render {

struct RenderView {
    // From the centre of the mesh's bounding box towards the camera (any length):
    // the default is a 3/4 view from front-right-above for +y up, +z front meshes
    // (the Stanford scans, libsnvr's samples).
    Vec3 direction = {0.55, 0.45, 1.0};
    Vec3 up = {0, 1, 0};  // projected to the image's upward direction
    int width = 1024, height = 1024;
    // Crop of the image plane: the full view scaled up `zoom` times around `center`,
    // given in normalised coordinates of the full view (u right, v down, 0..1).
    double zoom = 1;
    std::array<double, 2> center = {0.5, 0.5};
    // 0: orthographic; otherwise a perspective camera with this full field of view
    // in degrees (a few degrees make a slight perspective).
    double perspective_degrees = 0;
    // Gouraud shading with area-weighted vertex normals instead of flat face normals:
    // it hides faceting, so it is off for the pictures that look for terraces.
    bool smooth = false;
};

// Renders a grey material lit from the camera (ambient + Lambert + a little specular)
// on a white background; faces seen from behind (holes, wrong orientation) are tinted
// red. Writes an 8-bit RGB PNG through a temporary file renamed on success.
// Throws snvr::ParameterError for a bad view and snvr::IoError when writing fails.
void render_png(const Mesh& mesh, const std::string& path, const RenderView& view = {});

// The same picture as 8-bit RGB rows, top first.
std::vector<std::uint8_t> render_rgb(const Mesh& mesh, const RenderView& view = {});

// RGB rows as a PNG file's bytes; `path` names the file in messages.
std::string encode_png(const std::vector<std::uint8_t>& rgb, int width, int height, const std::string& path);

// What --preview writes, as PNG bytes: on the left the shell shaded from the default
// 3/4 view (flat, so terraces show; red where a face is seen from behind), on the
// right a cut through the middle of its box across `up` (a slicer's layer for +y-up
// data): material dark, voids white, so wall thickness and bubbles show. Each panel
// `size` pixels square.
std::string preview_png(const Mesh& mesh, const std::string& path, int size = 800);

}  // namespace snvr::render
