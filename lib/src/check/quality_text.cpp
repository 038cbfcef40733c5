// format_quality and quality_json (quality.hpp): the check's figures as a table for
// people and as JSON for programs.
#include <cmath>
#include <cstdio>
#include <string>

#include "number_text.hpp"
#include "snvr/quality.hpp"

namespace snvr {

namespace {

std::string fixed(double v, int digits = 3) {
    if (std::isnan(v)) return "n/a";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

const char* yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

std::string format_quality(const MeshQuality& q) {
    std::string s;
    s += "mesh:        " + std::to_string(q.vertices) + " vertices, " + std::to_string(q.triangles) +
         " triangles; closed " + yes_no(q.closed) + ", manifold " + yes_no(q.manifold) + ", oriented " +
         yes_no(q.oriented) + "\n";
    s += "pieces:      " + std::to_string(q.solids) + " solid, " + std::to_string(q.cavities) + " cavities (" +
         std::to_string(q.components) + " components); genus " + std::to_string(q.genus);
    if (q.open_components) s += " (" + std::to_string(q.open_components) + " open components left out)";
    s += "\n";
    s += "points:      " + std::to_string(q.points_inside) + " of " + std::to_string(q.points) + " inside (" +
         fixed(100 * q.inside_fraction, 2) + "%), " + std::to_string(q.points_outside) + " outside\n";
    s += "depth:       min " + fixed(q.depth_min) + " l (inside points), 1st percentile " + fixed(q.depth_p01) +
         " l (all, signed)";
    if (q.inside_disagreements) s += "; inside tests disagree on " + std::to_string(q.inside_disagreements);
    s += "\n";
    if (q.has_surface) {
        s += "offset err:  RMS " + fixed(q.offset_rms) + " h, mean " + fixed(q.offset_mean) + " h, max |e| " +
             fixed(q.offset_max) + " h   (l = " + detail::format_number(q.offset) +
             ", h = " + detail::format_number(q.voxel) + ")\n";
        s += "smoothness:  dihedral RMS " + fixed(q.dihedral_rms, 2) + " deg (" + std::to_string(q.interior_edges) +
             " interior edges), normal noise " + fixed(q.normal_noise, 2) + " deg\n";
    }
    s += "walls:       min " + fixed(q.wall_min) + " h = " + fixed(q.wall_min_2l) + " x 2l, 1st percentile " +
         fixed(q.wall_p01) + " h = " + fixed(q.wall_p01_2l) + " x 2l";
    if (q.wall_misses) s += "; " + std::to_string(q.wall_misses) + " rays met nothing";
    s += "\n";
    if (q.has_exact) s += "exact error: RMS " + fixed(q.exact_rms, 4) + " h, max " + fixed(q.exact_max, 4) + " h\n";
    s += "measured in " + fixed(q.seconds, 2) + " s\n";
    return s;
}

std::string quality_json(const MeshQuality& q) {
    std::string s = "{";
    const auto key = [&](const char* name) {
        if (s.size() > 1) s += ',';
        s += '"';
        s += name;
        s += "\":";
    };
    const auto count = [&](const char* name, std::size_t v) {
        key(name);
        s += std::to_string(v);
    };
    const auto number = [&](const char* name, double v) {
        key(name);
        if (std::isfinite(v))
            detail::append_number(s, v);
        else
            s += "null";
    };
    const auto flag = [&](const char* name, bool v) {
        key(name);
        s += v ? "true" : "false";
    };
    count("vertices", q.vertices);
    count("triangles", q.triangles);
    count("points", q.points);
    number("offset", q.offset);
    number("voxel", q.voxel);
    count("components", q.components);
    count("solids", q.solids);
    count("cavities", q.cavities);
    flag("closed", q.closed);
    flag("manifold", q.manifold);
    flag("oriented", q.oriented);
    key("genus");
    s += std::to_string(q.genus);
    count("open_components", q.open_components);
    count("points_inside", q.points_inside);
    count("points_outside", q.points_outside);
    number("inside_fraction", q.inside_fraction);
    number("depth_min_l", q.depth_min);
    number("depth_p01_l", q.depth_p01);
    if (q.has_surface) {
        count("inside_disagreements", q.inside_disagreements);
        number("offset_rms_h", q.offset_rms);
        number("offset_mean_h", q.offset_mean);
        number("offset_max_h", q.offset_max);
        number("dihedral_rms_deg", q.dihedral_rms);
        count("interior_edges", q.interior_edges);
        number("normal_noise_deg", q.normal_noise);
    }
    number("wall_min_h", q.wall_min);
    number("wall_p01_h", q.wall_p01);
    number("wall_min_2l", q.wall_min_2l);
    number("wall_p01_2l", q.wall_p01_2l);
    count("wall_misses", q.wall_misses);
    if (q.has_exact) {
        number("exact_rms_h", q.exact_rms);
        number("exact_max_h", q.exact_max);
    }
    number("seconds", q.seconds);
    s += '}';
    return s;
}

}  // namespace snvr
