#include "snvr/parameters.hpp"

#include <cmath>
#include <sstream>

#include "snvr/error.hpp"

namespace snvr {

double eps_of_cells(double m, double h) {
    return m * h / (2.0 * std::sqrt(2.0) * std::atanh(0.99));
}

namespace {

void require(bool ok, const std::string& what) {
    if (!ok) throw ParameterError(what);
}

std::string show(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// "<name> (--<option>) must be <range>, got <value>": the field and the command-line
// option it comes from, the value and the range.
std::string named(const char* name, const char* option) {
    return std::string(name) + " (--" + option + ")";
}

enum Ends { kClosed, kOpenBelow, kOpen };  // [lo, hi], (lo, hi], (lo, hi)

void in_range(double v, double lo, double hi, Ends ends, const char* name, const char* option, const char* unit) {
    const bool above = ends == kClosed ? v >= lo : v > lo, below = ends == kOpen ? v < hi : v <= hi;
    require(std::isfinite(v) && above && below, named(name, option) + " must be " +
                                                    (ends == kClosed ? "at least " : "above ") + show(lo) +
                                                    (ends == kOpen ? " and below " : " and at most ") + show(hi) +
                                                    unit + ", got " + show(v));
}

void require_positive(const std::optional<double>& v, const char* name, const char* option) {
    if (v) require(std::isfinite(*v) && *v > 0, named(name, option) + " must be a positive finite length, got " + show(*v));
}

}  // namespace

void scale_lengths(Parameters& p, double factor) {
    for (std::optional<double>* length : {&p.offset, &p.thickness, &p.voxel, &p.eps, &p.xi})
        if (*length) **length *= factor;
    if (p.box)
        for (Vec3& corner : *p.box)
            for (double& x : corner) x *= factor;
}

void Parameters::validate() const {
    using L = ParameterLimits;
    surface_fairing.validate();
    require(!(offset && thickness), "give the offset or the thickness, not both");
    require_positive(offset, "the offset", "offset");
    require_positive(thickness, "the thickness", "thickness");
    require_positive(voxel, "the voxel size", "voxel");
    require_positive(eps, "eps", "eps");
    require_positive(xi, "xi", "xi");
    in_range(resolution, L::min_resolution, L::max_resolution, kClosed, "the resolution", "resolution", " cells");
    in_range(offset_cells, L::min_offset_cells, L::max_offset_cells, kClosed, "the default offset", "offset-cells",
             " voxels");
    if (steps) in_range(*steps, 0, L::max_steps, kClosed, "the number of steps", "steps", "");
    if (dt) require(std::isfinite(*dt) && *dt > 0, named("dt", "dt") + " must be positive and finite, got " + show(*dt));
    in_range(dt_cells, 0, L::max_dt_cells, kOpenBelow, "dt / h^2", "dt-cells", "");
    in_range(smoothing_cells, 0, L::max_smoothing_cells, kClosed, "the flow time", "smoothing", " h^2");
    in_range(tube_inner, 0, L::max_tube_inner, kOpen, "the tube's inner side", "tube-inner", " x offset");
    in_range(tube_outer, 0, L::max_tube_outer, kOpenBelow, "the tube's outer side", "tube-outer", " x offset");
    in_range(upsample_spacing, L::min_upsample_spacing, 1, kClosed, "the added points' spacing", "upsample-spacing",
             " x offset");
    in_range(eps_cells, 0, L::max_width_cells, kOpenBelow, "eps", "eps-cells", " cells");
    in_range(xi_cells, 0, L::max_width_cells, kOpenBelow, "xi", "xi-cells", " cells");
    in_range(tol, 0, L::max_tol, kOpen, "the residual tolerance", "tol", "");
    in_range(max_cycles, 1, L::max_cycles, kClosed, "the V-cycles per step", "max-cycles", "");
    require(pre_smooth >= 0 && post_smooth >= 0 && pre_smooth + post_smooth >= 1,
            "the V-cycle needs at least one smoothing sweep");
    require(std::isfinite(omega) && omega > 0 && omega < 2, "omega must be in (0, 2), got " + show(omega));
    require(std::isfinite(band_xi) && band_xi >= 4 && band_xi <= 64, "band must be 4 to 64 xi, got " + show(band_xi));
    if (tile_cells)
        require(tile_cells >= L::min_tile_cells && tile_cells <= L::max_resolution && tile_cells % 8 == 0,
                "the tile size (--tile-cells) must be a multiple of 8 from " + std::to_string(L::min_tile_cells) +
                    " to " + std::to_string(L::max_resolution) + " cells, or 0 for none, got " +
                    std::to_string(tile_cells));
    if (tile_halo_cells)
        require(*tile_halo_cells >= 0 && *tile_halo_cells <= L::max_resolution && *tile_halo_cells % 8 == 0,
                "the tile halo (--tile-halo-cells) must be a multiple of 8 from 0 to " +
                    std::to_string(L::max_resolution) + " cells, got " + std::to_string(*tile_halo_cells));
    if (max_memory)
        require(*max_memory >= L::min_memory,
                "the memory budget (--max-memory) must be at least " + std::to_string(L::min_memory >> 20) +
                    " MiB, got " + std::to_string(*max_memory) + " bytes");
    if (box) {
        for (int a = 0; a < 3; ++a)
            require(std::isfinite((*box)[0][a]) && std::isfinite((*box)[1][a]) && (*box)[1][a] > (*box)[0][a],
                    "the grid box must have max > min on every axis");
    }
}

}  // namespace snvr
