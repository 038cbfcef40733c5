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

void require_positive(const std::optional<double>& v, const char* name) {
    if (v) require(std::isfinite(*v) && *v > 0, std::string(name) + " must be a positive finite length, got " + show(*v));
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
    require(!(offset && thickness), "give the offset or the thickness, not both");
    require_positive(offset, "offset");
    require_positive(thickness, "thickness");
    require_positive(voxel, "voxel size");
    require_positive(eps, "eps");
    require_positive(xi, "xi");
    require(resolution >= 16 && resolution <= 16384,
            "resolution must be between 16 and 16384 cells, got " + std::to_string(resolution));
    if (steps) require(*steps >= 0 && *steps <= 100000, "steps must be between 0 and 100000, got " + std::to_string(*steps));
    if (dt) require(std::isfinite(*dt) && *dt > 0, "dt must be positive and finite, got " + show(*dt));
    require(std::isfinite(dt_cells) && dt_cells > 0, "dt-cells must be positive, got " + show(dt_cells));
    require(std::isfinite(smoothing_cells) && smoothing_cells >= 0 && smoothing_cells <= 1e5,
            "smoothing must be between 0 and 1e5 cells^2, got " + show(smoothing_cells));
    require(std::isfinite(tube_inner) && tube_inner > 0 && tube_inner < 1,
            "the tube's inner side must be a share of the offset in (0, 1), got " + show(tube_inner));
    require(std::isfinite(tube_outer) && tube_outer > 0 && tube_outer <= 10,
            "the tube's outer side must be a share of the offset in (0, 10], got " + show(tube_outer));
    require(std::isfinite(eps_cells) && eps_cells > 0, "eps-cells must be positive, got " + show(eps_cells));
    require(std::isfinite(xi_cells) && xi_cells > 0, "xi-cells must be positive, got " + show(xi_cells));
    require(std::isfinite(tol) && tol > 0, "tol must be positive, got " + show(tol));
    require(max_cycles >= 1 && max_cycles <= 10000, "max-cycles must be between 1 and 10000, got " + std::to_string(max_cycles));
    require(pre_smooth >= 0 && post_smooth >= 0 && pre_smooth + post_smooth >= 1,
            "the V-cycle needs at least one smoothing sweep");
    require(std::isfinite(omega) && omega > 0 && omega < 2, "omega must be in (0, 2), got " + show(omega));
    require(std::isfinite(band_xi) && band_xi >= 4, "band must be at least 4 xi, got " + show(band_xi));
    if (box) {
        for (int a = 0; a < 3; ++a)
            require(std::isfinite((*box)[0][a]) && std::isfinite((*box)[1][a]) && (*box)[1][a] > (*box)[0][a],
                    "the grid box must have max > min on every axis");
    }
}

}  // namespace snvr
