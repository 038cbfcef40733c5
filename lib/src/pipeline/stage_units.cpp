// stage_units (report.hpp): each stage's seconds by its unit of work, and the bytes it
// must touch at the least. The bytes are a model, kept plain so that anyone can check it:
// the band's distance a float a band cell; the solver's fields written once to initialise
// them and each touched once a V-cycle (smoothing, residual and transfers all read every
// field of a level); the mesher reads the phase in the band and writes the mesh; the
// check reads the mesh; the write writes the files.
#include <cstdint>

#include "snvr/report.hpp"

namespace snvr {

namespace {

// A vertex's three doubles and a triangle's three indices, as the mesh holds them.
constexpr double kVertexBytes = 24, kTriangleBytes = 12;
constexpr double kBandValueBytes = sizeof(float);

}  // namespace

std::vector<StageUnit> stage_units(const RunReport& report) {
    const Shell& shell = report.shell;
    const Result& r = shell.run;
    const MeshReport& m = shell.quality.report;
    const double band = double(r.active_cells), triangles = double(m.triangles);
    const double steps = double(r.steps.size()), solver = double(r.solver_bytes);
    const double mesh_bytes = double(m.vertices) * kVertexBytes + triangles * kTriangleBytes;
    double written = 0;
    for (const RunFiles::Output& o : report.files.outputs) written += double(o.bytes);
    const auto unit = [](const char* stage, const char* name, double units, double seconds, double bytes) {
        return StageUnit{stage, name, units, units > 0 ? seconds / units * 1e9 : 0, bytes};
    };
    return {
        unit("distance", "band cell", band, r.seconds.distance, band * kBandValueBytes),
        unit("init", "band cell", band, r.seconds.init, solver),
        unit("steps", "band cell a step", band * steps, r.seconds.steps, double(report.cycles.total) * solver),
        unit("mesh", "triangle", triangles, shell.seconds.mesh, band * kBandValueBytes + mesh_bytes),
        unit("check", "triangle", triangles, shell.seconds.check, mesh_bytes),
        unit("write", "triangle", triangles, report.files.write_seconds, written),
    };
}

}  // namespace snvr
