// --report: the run as JSON for scripts (nlohmann-json). The check's figures come from
// the library's own quality_json, so each figure is named in one place.
#include <nlohmann/json.hpp>

#include "report.hpp"

#ifndef SNVR_VERSION
#define SNVR_VERSION "unknown"
#endif

namespace cli {

std::string report_json(const RunSummary& run) {
    using nlohmann::json;
    const snvr::Result& r = run.result;
    const snvr::Domain& d = r.domain;
    const CycleTotals cycles = cycle_totals(r);
    const snvr::MeshReport& m = run.quality.report;
    const double L = d.length_scale(), dt_cells = r.dt * (L / d.h) * (L / d.h);

    json outputs = json::array({{{"path", run.output}, {"kind", "mesh"}, {"bytes", run.output_bytes}}});
    if (!run.volume.empty())
        outputs.push_back({{"path", run.volume}, {"kind", "volume"}, {"bytes", run.volume_bytes}});
    const json report = {
        {"snvr_version", SNVR_VERSION},
        {"units", "mm"},  // every length below, and every output
        {"input",
         {{"path", run.input},
          {"points", run.points},
          {"units", run.units},
          {"to_millimetres", run.to_mm},
          {"origin_shift", {0.0 - run.shift[0], 0.0 - run.shift[1], 0.0 - run.shift[2]}},  // no -0
          {"origin_shift_why", run.shift == snvr::Vec3{0, 0, 0} ? "none"
                               : run.shift_by_default       ? "float32 output far from the origin (default)"
                                                            : "--origin center"}}},
        {"outliers", {{"dropped", run.outliers}, {"link", run.outlier_link}, {"file", run.outliers_file}}},
        {"pieces_dropped", {{"count", run.pieces.dropped}, {"volume", run.pieces.dropped_volume}}},
        {"outputs", outputs},
        {"grid",
         {{"nx", d.nx}, {"ny", d.ny}, {"nz", d.nz}, {"cells", d.cells()}, {"voxel", d.h}, {"levels", d.levels},
          {"active_cells", r.active_cells}}},
        {"offset", {{"length", r.offset}, {"voxels", r.offset / d.h}, {"thickness", 2 * r.offset}, {"why", r.offset_reason}}},
        {"sampling_gap", r.gap},
        {"eps", r.eps},
        {"xi", r.xi},
        {"flow",
         {{"steps", r.steps.size()},
          {"dt", r.dt},
          {"dt_cells", dt_cells},
          {"free_flow", !(r.tube_inner > 0)},
          {"tube", {r.offset - r.tube_inner, r.offset + r.tube_outer}}}},
        {"backend", r.backend},
        {"memory", {{"solver_bytes", r.solver_bytes}, {"peak_rss_bytes", peak_rss_bytes()}}},
        {"v_cycles", {{"total", cycles.total}, {"most_in_a_step", cycles.most_in_a_step}, {"not_converged", cycles.not_converged}}},
        {"seconds",
         {{"read", run.seconds.read},
          {"outliers", run.seconds.outliers},
          {"domain", r.seconds.domain},
          {"distance", r.seconds.distance},
          {"init", r.seconds.init},
          {"steps", r.seconds.steps},
          {"mesh", run.seconds.mesh},
          {"write", run.seconds.write},
          {"check", run.seconds.check},
          {"total", run.seconds.total}}},
        {"size", {run.size[0], run.size[1], run.size[2]}},
        {"mesh",
         {{"triangles", m.triangles},
          {"vertices", m.vertices},
          {"components", m.components},
          {"solid_pieces", m.solids},
          {"closed", m.closed()},
          {"manifold", m.manifold()},
          {"oriented", m.oriented()},
          {"zero_area_triangles", m.zero_area_triangles}}},
        {"check", json::parse(snvr::quality_json(run.quality))},
        {"warnings", run.warnings},
    };
    return report.dump(2) + "\n";
}

}  // namespace cli
