#include "quality.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "host_measures.hpp"
#include "snvr/shell.hpp"
#include "snvr/snvr.hpp"
#ifdef SNVR_HAVE_OPENVDB
#include "openvdb_shell.hpp"
#endif
#include "snvr/render.hpp"
#include "snvr/shapes.hpp"

namespace snvr::bench {

namespace {

double longest_extent(const PointSet& points) {
    if (points.empty()) throw std::runtime_error("no points");
    Vec3 lo = points[0], hi = lo;
    for (const Vec3& p : points)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
}

double z_extent(const PointSet& points) {
    double lo = points.at(0)[2], hi = lo;
    for (const Vec3& p : points) lo = std::min(lo, p[2]), hi = std::max(hi, p[2]);
    return hi - lo;
}

// The input of a run, and its voxel and offset in world units.
struct Input {
    PointSet points;
    double spacing = 0;  // shapes: the sampling spacing used (world)
    double voxel = 0, offset = 0, reference_voxel = 0;
};

Input make_input(const QualityRun& run, const std::string& data_dir) {
    const QualityCase& c = run.c;
    Input in;
    if (!c.file.empty()) {
        in.points = read_points(data_dir + "/" + c.file);
    } else {
        // The spacing is given in reference voxels, which depend on the points' extent:
        // a coarse sample has (nearly) the same extent.
        const double h0 = longest_extent(shapes::by_name(c.shape, 0.02)) / run.reference;
        in.spacing = c.spacing * h0;
        in.points = shapes::by_name(c.shape, in.spacing);
    }
    const double extent = longest_extent(in.points);
    in.voxel = extent / run.resolution;
    in.reference_voxel = extent / run.reference;
    in.offset = c.offset_from_gap ? z_extent(in.points) / 3 : c.offset * in.reference_voxel;
    return in;
}

// The zoom's centre, in the full view's normalised coordinates: the vertex farthest
// towards the camera. It is always visible, and the surface curves away from it on
// every side, so the crop shows a curved region of any shape. The framing repeats
// render_png's: the projected bounding box fitted with its 4% margin.
std::array<double, 2> zoom_centre(const Mesh& mesh, const render::RenderView& view, double zoom) {
    const auto dot = [](const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const auto unit = [&](const Vec3& a) {
        const double n = std::sqrt(dot(a, a));
        return Vec3{a[0] / n, a[1] / n, a[2] / n};
    };
    const auto cross = [](const Vec3& a, const Vec3& b) {
        return Vec3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    };
    const Vec3 z = unit(view.direction), x = unit(cross(view.up, z)), y = cross(z, x);
    double lo_u = INFINITY, hi_u = -INFINITY, lo_v = INFINITY, hi_v = -INFINITY, best = -INFINITY, bu = 0, bv = 0;
    for (const Vec3& p : mesh.vertices) {
        const double u = dot(p, x), v = dot(p, y), depth = dot(p, z);
        lo_u = std::min(lo_u, u), hi_u = std::max(hi_u, u), lo_v = std::min(lo_v, v), hi_v = std::max(hi_v, v);
        if (depth > best) best = depth, bu = u, bv = v;
    }
    const double W = view.width, H = view.height, margin = 1.04;
    const double scale = std::min(W / std::max(hi_u - lo_u, 1e-300), H / std::max(hi_v - lo_v, 1e-300)) / margin;
    const double cu = 0.5 + (bu - 0.5 * (lo_u + hi_u)) * scale / W, cv = 0.5 - (bv - 0.5 * (lo_v + hi_v)) * scale / H;
    // Keep the crop inside the full view.
    const double edge = 0.5 / zoom;
    return {std::clamp(cu, edge, 1 - edge), std::clamp(cv, edge, 1 - edge)};
}

void previews(const Mesh& mesh, const QualityRun& run, Record& rec) {
    const std::string base = "quality_" + run.c.name + "_" + std::to_string(run.resolution) + "_" + run.tool;
    render::RenderView view;
    view.width = view.height = run.png_size;
    render::render_png(mesh, run.png_dir + "/" + base + ".png", view);
    view.zoom = 3;
    view.center = zoom_centre(mesh, view, view.zoom);
    render::render_png(mesh, run.png_dir + "/" + base + "_zoom.png", view);
    rec.set("png", base + ".png").set("png_zoom", base + "_zoom.png");
}

void describe_quality(Record& r, const MeshQuality& q) {
    r.set("vertices", double(q.vertices)).set("triangles", double(q.triangles));
    r.set("components", double(q.components)).set("solids", double(q.solids)).set("cavities", double(q.cavities));
    r.set("closed", q.closed ? "yes" : "no").set("manifold", q.manifold ? "yes" : "no").set("oriented", q.oriented ? "yes" : "no");
    r.set("genus", double(q.genus)).set("open_components", double(q.open_components));
    r.set("inside_pct", 100 * q.inside_fraction).set("depth_min_l", q.depth_min).set("depth_p01_l", q.depth_p01);
    r.set("inside_disagreements", double(q.inside_disagreements));
    r.set("offset_rms_h", q.offset_rms).set("offset_mean_h", q.offset_mean).set("offset_max_h", q.offset_max);
    r.set("dihedral_deg", q.dihedral_rms).set("normal_noise_deg", q.normal_noise);
    r.set("wall_min_2l", q.wall_min_2l).set("wall_p01_2l", q.wall_p01_2l).set("wall_misses", double(q.wall_misses));
    if (q.has_exact) r.set("exact_rms_h", q.exact_rms).set("exact_max_h", q.exact_max);
    r.set("quality_s", q.seconds);
}

}  // namespace

std::vector<QualityCase> quality_cases(const std::string& data_dir, bool all_scans) {
    namespace fs = std::filesystem;
    std::vector<QualityCase> out;
    const char* first[] = {"bunny", "igea", "armadillo"};
    std::vector<std::string> stems(std::begin(first), std::end(first));
    if (all_scans) {
        std::vector<std::string> more;
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(data_dir, ec))
            if (e.path().extension() == ".ply" && std::find(stems.begin(), stems.end(), e.path().stem().string()) == stems.end())
                more.push_back(e.path().stem().string());
        std::sort(more.begin(), more.end());
        stems.insert(stems.end(), more.begin(), more.end());
    }
    for (const std::string& s : stems)
        if (fs::exists(data_dir + "/" + s + ".ply")) {
            QualityCase c;
            c.name = s;
            c.file = s + ".ply";
            c.why = "scan; l = 2.5 reference voxels";
            out.push_back(c);
        }
    const auto shape = [](const char* name, double spacing, double offset, const char* why) {
        QualityCase c;
        c.name = c.shape = name;
        c.spacing = spacing;
        c.offset = offset;
        c.why = why;
        return c;
    };
    QualityCase sheets = shape("sheets", 1, 0, "two sheets 3 l apart: l = gap / 3; spacing 1 reference voxel");
    sheets.offset_from_gap = true;
    out.push_back(sheets);
    out.push_back(shape("mobius", 1, 2.5, "open non-orientable strip; l = 2.5, spacing 1 reference voxel"));
    out.push_back(shape("helicoid", 1, 2.5, "l = 2.5, spacing 1 reference voxel"));
    // by_name's noise is 0.3 spacings: a spacing of one voxel gives sigma = 0.3 h.
    out.push_back(shape("noisy-sphere", 1, 6.4, "Gaussian noise sigma = 0.3 h, l = 6.4 h (reference voxels)"));
    out.push_back(shape("varying-sphere", 1, 2.5, "10x density variation: spacing 1 to 3.2 reference voxels, l = 2.5"));
    out.push_back(shape("torus", 1.7 * 2.5, 2.5, "undersampled: given l = 2.5 reference voxels, spacing 1.7 l"));
    out.push_back(shape("lidar", 0.5, 2.5, "scan lines 2 reference voxels apart, 0.5 along them; l = 2.5"));
    return out;
}

bool quality_has_openvdb() {
#ifdef SNVR_HAVE_OPENVDB
    return true;
#else
    return false;
#endif
}

Record measure_quality_run(const QualityRun& run, const std::string& data_dir) {
    const Input in = make_input(run, data_dir);
    Record rec;
    rec.set("section", "quality").set("case", run.c.name).set("resolution", run.resolution).set("tool", run.tool);
    rec.set("reference", run.reference).set("points", double(in.points.size())).set("voxel", in.voxel).set("offset", in.offset);
    rec.set("offset_h", in.offset / in.voxel).set("setting", run.c.why);
    if (in.spacing > 0) rec.set("spacing", in.spacing);

    Mesh mesh;
    if (run.tool == "snvr") {
        ShellSettings s;  // snvr-cl's job and defaults, but for the voxel and the offset, on every point given
        s.params.voxel = in.voxel;
        s.params.offset = in.offset;
        s.params.device = run.device;
        s.drop_outliers = false;
        warmup(s.params.device, s.params.precision == Precision::Single);  // the kernels' build stays out of the timed run
        const Shell shell = make_shell(in.points, s);
        mesh = shell.mesh;
        const Result& res = shell.run;
        rec.set("backend", res.backend).set("grid", std::to_string(res.domain.nx) + "x" + std::to_string(res.domain.ny) + "x" +
                                                        std::to_string(res.domain.nz));
        rec.set("reconstruct_s", shell.seconds.reconstruct).set("mesh_s", shell.seconds.mesh);
        rec.set("seconds", shell.seconds.reconstruct + shell.seconds.mesh);
    } else if (run.tool == "openvdb") {
#ifdef SNVR_HAVE_OPENVDB
        peers::PeerShell shell = peers::openvdb_shell(in.points, in.voxel, in.offset);
        mesh = std::move(shell.mesh);
        rec.set("backend", "openvdb").set("grid", "sparse").set("reconstruct_s", shell.seconds_level_set + shell.seconds_filter);
        rec.set("mesh_s", shell.seconds_mesh).set("seconds", shell.seconds_total);
#else
        throw std::runtime_error("the OpenVDB peer is not built");
#endif
    } else {
        throw std::runtime_error("unknown tool " + run.tool);
    }
    rec.set("peak_rss_mib", peak_rss_mib());
    if (mesh.triangles.empty()) throw std::runtime_error("empty mesh");

    std::function<double(const Vec3&)> exact;
    if (!run.c.shape.empty()) {
        // The exact offset surface is where the distance to the noise-free surface is l.
        const auto distance = shapes::exact_distance_by_name(run.c.shape, in.spacing);
        exact = [distance, l = in.offset](const Vec3& x) { return std::abs(distance(x) - l); };
    }
    describe_quality(rec, measure_quality(mesh, in.points, in.offset, in.voxel, exact));
    if (!run.png_dir.empty()) previews(mesh, run, rec);
    return rec;
}

}  // namespace snvr::bench
