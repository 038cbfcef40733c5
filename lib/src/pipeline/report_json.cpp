// report_json (report.hpp): the run as JSON for scripts (nlohmann-json; snvr-cl's
// --report, Python's Shell.report). The check's figures come from quality_json, so each
// figure is named in one place.
#include <nlohmann/json.hpp>

#include "snvr/report.hpp"

#ifndef SNVR_VERSION
#define SNVR_VERSION "unknown"
#endif

namespace snvr {

std::string report_json(const RunReport& report) {
    using nlohmann::json;
    const Shell& run = report.shell;
    const Result& r = run.run;
    const RunFiles& files = report.files;
    const Domain& d = r.domain;
    const CycleTotals& cycles = report.cycles;
    const MeshReport& m = run.quality.report;
    const double L = d.length_scale(), dt_cells = r.dt * (L / d.h) * (L / d.h);

    json check = json::parse(quality_json(run.quality));
    check["walls_on"] = run.quality.walls_on;
    json per_unit = json::object();
    for (const StageUnit& u : stage_units(report))
        per_unit[u.stage] = {{"unit", u.unit}, {"units", u.units}, {"ns", u.ns}, {"floor_bytes", u.floor_bytes}};
    json outputs = json::array();
    for (const RunFiles::Output& o : files.outputs) outputs.push_back({{"path", o.path}, {"kind", o.kind}, {"bytes", o.bytes}});
    const json doc = {
        {"snvr_version", SNVR_VERSION},
        {"units", "mm"},  // every length below, and every output
        {"input",
         {{"path", files.input},
          {"points", run.points},
          {"units", run.units},
          {"to_millimetres", run.to_millimetres},
          {"origin_shift", {0.0 - run.shift[0], 0.0 - run.shift[1], 0.0 - run.shift[2]}},  // no -0
          {"origin_shift_why", run.shift == Vec3{0, 0, 0} ? "none"
                               : run.shift_by_default       ? "float32 output far from the origin (default)"
                                                            : "--origin center"}}},
        {"outliers", {{"dropped", run.outliers.points.size()}, {"link", run.outliers.link}, {"file", files.outliers_file}}},
        {"point_clusters", run.clusters},
        {"pieces_dropped", {{"count", run.pieces.dropped}, {"volume", run.pieces.dropped_volume}}},
        {"outputs", outputs},
        {"grid",
         {{"nx", d.nx}, {"ny", d.ny}, {"nz", d.nz}, {"cells", d.cells()}, {"voxel", d.h}, {"levels", d.levels},
          {"origin", {d.origin[0], d.origin[1], d.origin[2]}},
          {"active_cells", r.active_cells}}},
        {"offset", {{"length", r.offset}, {"voxels", r.offset / d.h}, {"thickness", 2 * r.offset}, {"why", r.offset_reason}}},
        {"sampling_gap", r.gap},
        {"sampling_holes", {{"share", r.hole_share}, {"points_added", r.hole_fills}, {"wider_than", r.hole_least},
                             {"sought_elsewhere", r.holes_sought_elsewhere}}},
        {"upsampled",
         {{"points_added", r.upsampled}, {"spacing", r.upsample_spacing}, {"made_elsewhere", r.upsampled_elsewhere}}},
        {"eps", r.eps},
        {"xi", r.xi},
        {"flow",
         {{"steps", r.steps.size()},
          {"dt", r.dt},
          {"dt_cells", dt_cells},
          {"free_flow", !(r.tube_inner > 0)},
          {"tube", {r.offset - r.tube_inner, r.offset + r.tube_outer}}}},
        {"tiles",
         {{"core_cells", r.tiles.core_cells},
          {"halo_cells", r.tiles.halo_cells},
          {"halo_derived", r.tiles.halo_derived},
          {"processes", r.tiles.processes},
          {"count", r.tiles.tiles},
          {"run", r.tiles.run},
          {"reruns", r.tiles.reruns},
          {"most_points", r.tiles.most_points},
          {"most_band_cells", r.tiles.most_band_cells},
          {"cells_run_over_cores", r.tiles.cells_run},
          {"seconds", r.tiles.seconds},
          {"busiest_over_mean", r.tiles.busiest_over_mean},
          {"bytes_received", r.tiles.bytes_received},
          {"face_bytes_received", r.tiles.face_bytes},
          {"faces_received", r.tiles.faces_received},
          {"points_sent", r.tiles.points_sent},
          {"points_from_ranges", r.tiles.points_from_ranges},
          {"check_walls_elsewhere", r.tiles.check_walls},
          {"check_points_elsewhere", r.tiles.check_points},
          {"check_bytes_sent", r.tiles.check_bytes},
          {"check_points_far", r.tiles.check_points_far},
          {"guard_points_elsewhere", r.tiles.guard_points},
          {"guard_bytes_sent", r.tiles.guard_bytes},
          {"surface_slabs", r.tiles.slabs},
          {"slab_ghost_planes", r.tiles.slab_ghost},
          {"slab_bytes_sent", r.tiles.slab_bytes},
          {"guard_on_slabs", r.tiles.guard_slabs},
          {"guard_slab_points", r.tiles.guard_slab_points},
          {"guard_ghosts_differing", r.tiles.guard_ghosts_differing},
          {"guard_run_again_whole", r.tiles.guard_rerun},
          {"check_topology_by_slabs", r.tiles.check_topology_slabs},
          {"surface_kept_in_slabs", r.tiles.slabs_kept}}},
        {"backend", r.backend},
        {"memory",
         {{"solver_bytes", r.solver_bytes},
          {"peak_rss_bytes", report.peak_rss_bytes},
          {"huge_page_bytes", report.huge_page_bytes},
          {"budget_bytes", r.memory.budget},
          {"budget_given", r.memory.budget_given},
          {"held_bytes", r.memory.held},
          {"near_bricks", r.memory.near_bricks},
          {"estimated",
           {{"whole_solver", r.memory.whole_solver},
            {"tile_solver", r.memory.tile_solver},
            {"field", r.memory.field},
            {"surfaces", r.memory.surfaces},
            {"mesh_and_check", r.memory.mesh},
            {"grid", r.memory.grid},
            {"runtime", r.memory.runtime},
            {"peak", r.memory.estimated_peak}}},
          {"bound_by", r.memory.bound},
          {"tiled_by_budget", r.memory.tiled_by_budget},
          {"spilled",
           {{"arrays", r.memory.spilled_arrays},
            {"most_bytes", r.memory.spilled_bytes},
            {"trims", r.memory.spill_trims},
            {"folder", r.memory.spill_folder},
            {"storage_read_bytes", r.memory.storage_read},
            {"storage_written_bytes", r.memory.storage_written}}}}},
        {"v_cycles", {{"total", cycles.total}, {"most_in_a_step", cycles.most_in_a_step}, {"not_converged", cycles.not_converged}}},
        {"seconds",
         {{"read", files.read_seconds},
          {"outliers", run.seconds.outliers},
          {"domain", r.seconds.domain},
          {"distance", r.seconds.distance},
          {"init", r.seconds.init},
          {"steps", r.seconds.steps},
          {"mesh", run.seconds.mesh},
          {"seams", r.seconds.seams},  // within mesh: a tiled run's seams and weld
          {"write", files.write_seconds},
          {"check", run.seconds.check},
          {"total", report.total_seconds}}},
        {"per_unit", per_unit},
        {"size", {run.size[0], run.size[1], run.size[2]}},
        {"mesh",
         {{"triangles", m.triangles},
          {"vertices", m.vertices},
          {"components", m.components},
          {"solid_pieces", m.solids},
          {"closed", m.closed()},
          {"manifold", m.manifold()},
          {"oriented", m.oriented()},
          {"zero_area_triangles", m.zero_area_triangles},
          {"depth_guard",
           {{"near_vertices", run.guard.near_vertices},
            {"moved_vertices", run.guard.moved_vertices},
            {"repair_rounds", run.guard.repair_rounds},
            {"shallow_points", run.guard.shallow_points},
            {"lone_points", run.guard.lone_points}}}}},
        {"check", check},
        {"warnings", run.warnings},
    };
    return doc.dump(2) + "\n";
}

}  // namespace snvr
