// Whole reconstructions: accuracy against the paper's Table 2, and printable meshes
// (closed, manifold, outward, every input point inside) for closed, open and real input.
#include <doctest/doctest.h>

#include <cstdio>

#include "snvr/snvr.hpp"
#include "table2.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;

namespace {

// Everything a slicer needs, and every point inside the printed solid.
void check_printable(const Mesh& mesh, const PointSet& points, std::size_t expected_components) {
    const MeshReport rep = check_mesh(mesh);
    const std::size_t inside = count_points_inside(mesh, points);
    std::printf("  %zu triangles, %zu components, closed %d, manifold %d, oriented %d, %zu of %zu points inside\n",
                rep.triangles, rep.components, rep.closed(), rep.manifold(), rep.oriented(), inside, points.size());
    CHECK(rep.closed());
    CHECK(rep.manifold());
    CHECK(rep.oriented());
    CHECK(rep.components == expected_components);
    CHECK(rep.solids == 1);  // one printed part; a closed input's inner sheet bounds a cavity
    CHECK(inside == points.size());
}

}  // namespace

TEST_CASE("Table 2 at 128^3: grown and shrunk errors below the paper's, on both backends, at the defaults") {
    // Paper set-up: l = 0.05, eps = 0.005 (0.64 h); points at spacing h/2; our default
    // flow (1.5 h^2 in steps of 0.25 h^2, the tube) and xi (4 cells). Measured: 2.0-4.8x
    // below the paper on every entry (sphere 7.05e-4 / 7.41e-4 against 1.804e-3 / 2.013e-3);
    // at 256^3 4-10x (bench_table2). The paper's fixed dt missed the sphere's grown sheet.
    const int resolution = 128;
    for (const char* device : {"openmp", "opencl"})
    for (const table2::Shape& shape : table2::shapes()) {
        CAPTURE(device);
        const PointSet points = shapes::by_name(shape.name, 0.5 / resolution);
        Parameters p = table2::parameters(resolution);
        p.device = device;
        const Result r = reconstruct(points, p);
        const Mesh mesh = extract_isosurface(r.phi, r.domain, 0.0, Interpolation::PhaseField);
        const table2::Errors e = table2::surface_errors(mesh, shape, 0.05);
        std::printf("%-6s %-8s grown %.3e (paper %.3e)  shrunk %.3e (paper %.3e)\n", device, shape.name.c_str(), e.grown,
                    shape.paper_grown_128, e.shrunk, shape.paper_shrunk_128);
        CHECK(e.grown_vertices > 1000);
        CHECK(e.shrunk_vertices > 1000);
        CHECK(e.grown <= 0.7 * shape.paper_grown_128);
        CHECK(e.shrunk <= 0.7 * shape.paper_shrunk_128);
        check_printable(mesh, points, 2);
    }
}

TEST_CASE("an open surface (half sphere, paper Fig. 5) becomes one closed shell around it") {
    const PointSet points = shapes::half_sphere({0.5, 0.5, 0.5}, 0.35, 0.004);
    Parameters p;
    p.device = "openmp";  // test_opencl_runs runs it on OpenCL too
    p.resolution = 96;
    const Result r = reconstruct(points, p);
    check_printable(extract_isosurface(r.phi, r.domain, 0.0, Interpolation::PhaseField), points, 1);
}

TEST_CASE("a real scan (the Stanford bunny) gives a printable shell") {
    const PointSet points = read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply");
    Parameters p;
    p.device = "openmp";  // test_opencl_runs runs it on OpenCL too
    p.resolution = 128;
    p.steps = 4;
    const Result r = reconstruct(points, p);
    std::printf("bunny: offset %.5g (%s)\n", r.offset, r.offset_reason.c_str());
    check_printable(extract_isosurface(r.phi, r.domain, 0.0, Interpolation::PhaseField), points, 1);
}
