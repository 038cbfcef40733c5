// The Python module `snvr`: make_shell on numpy points, the readers, the writers.
// Arrays of float32 or float64 that are C-contiguous (N, 3) are read in place; any other
// array-like is converted once. The solver runs without the GIL; the progress callback,
// and Ctrl-C, can cancel it.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Python.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "io/point_readers.hpp"
#include "spilled_memory.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_io.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/report.hpp"
#include "snvr/shell.hpp"
#include "snvr/stopwatch.hpp"

namespace py = pybind11;

namespace {

// An (N, 3) array of points as a cloud: float32 and float64 C-contiguous arrays in place,
// anything else converted to float64 once.
snvr::PointCloud cloud_of(const py::handle& points) {
    const auto check_shape = [](const py::array& a) {
        if (a.ndim() != 2 || a.shape(1) != 3)
            throw py::value_error("points must be an (N, 3) array, got shape " +
                                  std::string(py::str(py::tuple(py::cast(std::vector<py::ssize_t>(
                                      a.shape(), a.shape() + a.ndim()))))));
    };
    constexpr int c_style = py::array::c_style;
    if (py::isinstance<py::array_t<float, c_style>>(points)) {
        const auto a = py::reinterpret_borrow<py::array_t<float, c_style>>(points);
        check_shape(a);
        return snvr::PointCloud(a.data(), std::size_t(a.shape(0)));
    }
    if (py::isinstance<py::array_t<double, c_style>>(points)) {
        const auto a = py::reinterpret_borrow<py::array_t<double, c_style>>(points);
        check_shape(a);
        return snvr::PointCloud(a.data(), std::size_t(a.shape(0)));
    }
    const auto a = py::array_t<double, c_style | py::array::forcecast>::ensure(points);
    if (!a) throw py::value_error("points must be an (N, 3) array of numbers");
    check_shape(a);
    return snvr::PointCloud(a.data(), std::size_t(a.shape(0)));
}

py::array_t<double> array_of(const snvr::PointSet& points) {
    py::array_t<double> out({py::ssize_t(points.size()), py::ssize_t(3)});
    auto v = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < points.size(); ++i)
        for (int a = 0; a < 3; ++a) v(py::ssize_t(i), a) = points[i][std::size_t(a)];
    return out;
}

// The shell and what came with it, as Python sees it.
struct PyShell {
    snvr::Shell shell;
    std::size_t input_points = 0;
    snvr::RunFiles files;  // the file read, when a path was given

    // The report's JSON view as a dict: the same keys and figures as snvr-cl's --report.
    py::object report() const {
        return py::module_::import("json").attr("loads")(snvr::report_json(snvr::make_report(shell, files)));
    }

    py::array_t<double> vertices() const { return array_of(shell.mesh.vertices); }
    py::array_t<std::uint32_t> faces() const {
        py::array_t<std::uint32_t> out({py::ssize_t(shell.mesh.triangles.size()), py::ssize_t(3)});
        auto v = out.mutable_unchecked<2>();
        for (std::size_t t = 0; t < shell.mesh.triangles.size(); ++t)
            for (int c = 0; c < 3; ++c) v(py::ssize_t(t), c) = shell.mesh.triangles[t][std::size_t(c)];
        return out;
    }
    py::array_t<bool> outlier_mask() const {
        py::array_t<bool> out(std::vector<py::ssize_t>{py::ssize_t(input_points)});
        auto v = out.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < py::ssize_t(input_points); ++i) v(i) = false;
        for (std::size_t i : shell.outliers.input_indices) v(py::ssize_t(i)) = true;
        return out;
    }
    void write(const std::string& path) const {
        py::gil_scoped_release unlocked;
        snvr::write_mesh(shell.mesh, path);
    }
};

PyShell shell(const py::handle& points, std::optional<int> resolution, std::optional<double> voxel,
              std::optional<double> offset, std::optional<double> thickness, std::optional<double> offset_cells,
              bool keep_outliers, const std::string& origin, int fairing, double min_piece_volume,
              std::size_t keep_largest, bool measure, std::optional<double> smoothing, std::optional<double> dt_cells,
              std::optional<int> steps, std::optional<double> tube_inner, std::optional<double> tube_outer,
              bool free_flow, bool points_as_given, std::optional<double> eps_cells, std::optional<double> xi_cells,
              std::optional<double> tol, std::optional<int> max_cycles, int tile_cells,
              std::optional<int> tile_halo_cells, std::optional<std::size_t> max_memory, const std::string& temp_dir, const std::string& precision, const std::string& device, const std::string& written_as, bool keep_field,
              const std::string& units, double scale, const py::object& progress) {
    snvr::ShellSettings s;
    snvr::Parameters& p = s.params;
    if (resolution) p.resolution = *resolution;
    p.voxel = voxel;
    p.offset = offset;
    p.thickness = thickness;
    if (offset_cells) p.offset_cells = *offset_cells;
    if (smoothing) p.smoothing_cells = *smoothing;
    if (dt_cells) p.dt_cells = *dt_cells;
    p.steps = steps;
    if (tube_inner) p.tube_inner = *tube_inner;
    if (tube_outer) p.tube_outer = *tube_outer;
    p.keep_offset = !free_flow;
    p.add_points = !points_as_given;
    if (eps_cells) p.eps_cells = *eps_cells;
    if (xi_cells) p.xi_cells = *xi_cells;
    if (tol) p.tol = *tol;
    if (max_cycles) p.max_cycles = *max_cycles;
    p.tile_cells = tile_cells;
    p.tile_halo_cells = tile_halo_cells;
    p.max_memory = max_memory;
    p.temp_dir = temp_dir;
    if (precision == "double") p.precision = snvr::Precision::Double;
    else if (precision == "float") p.precision = snvr::Precision::Single;
    else throw py::value_error("precision must be 'float' or 'double', got '" + precision + "'");
    p.device = device;
    if (origin == "auto") s.origin = snvr::ShellOrigin::Auto;
    else if (origin == "keep") s.origin = snvr::ShellOrigin::Keep;
    else if (origin == "center") s.origin = snvr::ShellOrigin::Centre;
    else throw py::value_error("origin must be 'auto', 'keep' or 'center', got '" + origin + "'");
    s.drop_outliers = !keep_outliers;
    s.fairing.passes = fairing;
    s.pieces.min_volume = min_piece_volume;
    s.pieces.keep_largest = keep_largest;
    s.measure = measure;
    s.written_as = written_as;
    s.keep_field = keep_field;
    s.units = units;
    s.scale = scale;

    PyShell out;
    snvr::PointCloud cloud;
    if (py::isinstance<py::str>(points) || py::hasattr(points, "__fspath__")) {  // a file, read as snvr-cl reads it
        out.files.input = py::str(py::module_::import("os").attr("fspath")(points));
        py::gil_scoped_release unlocked;
        snvr::Stopwatch read;
        cloud = std::move(snvr::read_input(out.files.input, p).points);
        out.files.read_seconds = read.lap();
    } else {
        // Under a budget, the cloud's arrays beyond it go to files, as read_input's do.
        const snvr::detail::SpillScope spill(p.max_memory.value_or(0), 0, p.temp_dir);
        cloud = cloud_of(points);
    }
    out.input_points = cloud.size();
    // Called without the GIL: takes it, lets Python see Ctrl-C, asks the callback.
    const snvr::ProgressCallback ask = [&progress](const snvr::Progress& p) {
        py::gil_scoped_acquire locked;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // KeyboardInterrupt: the run stops
        if (progress.is_none()) return true;
        const py::object answer = progress(p.stage, p.step, p.steps);
        return answer.is_none() || answer.cast<bool>();
    };
    {
        py::gil_scoped_release unlocked;
        out.shell = snvr::make_shell(std::move(cloud), s, ask);
    }
    return out;
}

}  // namespace

PYBIND11_MODULE(snvr, m) {
    m.doc() = "libsnvr: a thin, closed, printable shell around a point cloud (Allen-Cahn narrow volume, Li et al. 2014).";

    static py::exception<snvr::Cancelled> cancelled(m, "Cancelled", PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr e) {
        try {
            if (e) std::rethrow_exception(e);
        } catch (const snvr::Cancelled& x) {
            cancelled(x.what());
        } catch (const snvr::IoError& x) {
            PyErr_SetString(PyExc_OSError, x.what());
        } catch (const snvr::ParameterError& x) {
            PyErr_SetString(PyExc_ValueError, x.what());
        } catch (const snvr::InputError& x) {
            PyErr_SetString(PyExc_ValueError, x.what());
        } catch (const snvr::ResourceError& x) {
            PyErr_SetString(PyExc_MemoryError, x.what());
        } catch (const snvr::Error& x) {
            PyErr_SetString(PyExc_RuntimeError, x.what());
        }
    });

    py::class_<PyShell>(m, "Shell", "The shell and everything the run reports.")
        .def_property_readonly("vertices", &PyShell::vertices, "(V, 3) float64: the mesh's vertices, as written_as holds them")
        .def_property_readonly("faces", &PyShell::faces, "(F, 3) uint32: each triangle's vertices, outward")
        .def_property_readonly("outlier_mask", &PyShell::outlier_mask, "(N,) bool: the input points dropped as outliers")
        .def_property_readonly("outliers", [](const PyShell& s) { return array_of(s.shell.outliers.points); },
                               "(K, 3) float64: the points dropped, where they were given")
        .def_property_readonly("shift", [](const PyShell& s) {
            return py::make_tuple(s.shell.shift[0], s.shell.shift[1], s.shell.shift[2]);
        }, "what was subtracted from the points (origin='center', or 'auto' where written_as is STL or 3MF and "
           "float32 would move the shell): add it back to place the shell")
        .def_property_readonly("warnings", [](const PyShell& s) { return s.shell.warnings; })
        .def_property_readonly("report", &PyShell::report,
                               "what snvr-cl's --report says (its JSON as a dict; lengths in millimetres)")
        .def("write", &PyShell::write, py::arg("path"),
             "Writes the mesh: .stl, .ply, .obj or .3mf (millimetres), by the extension.")
        // The libraries users hold, imported only when asked for.
        .def("to_open3d", [](const PyShell& s) {
            const py::module_ o3d = py::module_::import("open3d");
            const py::object faces = s.faces().attr("astype")("int32");
            return o3d.attr("geometry").attr("TriangleMesh")(o3d.attr("utility").attr("Vector3dVector")(s.vertices()),
                                                             o3d.attr("utility").attr("Vector3iVector")(faces));
        }, "The mesh as an open3d.geometry.TriangleMesh (imports open3d).")
        .def("to_trimesh", [](const PyShell& s) {
            return py::module_::import("trimesh").attr("Trimesh")(py::arg("vertices") = s.vertices(),
                                                                  py::arg("faces") = s.faces(), py::arg("process") = false);
        }, "The mesh as a trimesh.Trimesh (imports trimesh).")
        .def("to_pyvista", [](const PyShell& s) {
            const py::module_ np = py::module_::import("numpy");
            const py::array_t<std::uint32_t> f = s.faces();
            const py::object cells = np.attr("hstack")(py::make_tuple(
                np.attr("full")(py::make_tuple(f.shape(0), 1), 3, py::arg("dtype") = "int64"), f.attr("astype")("int64")));
            return py::module_::import("pyvista").attr("PolyData")(s.vertices(), cells.attr("ravel")());
        }, "The mesh as a pyvista.PolyData (imports pyvista).")
        .def("__repr__", [](const PyShell& s) {
            return "<snvr.Shell: " + std::to_string(s.shell.mesh.triangles.size()) + " triangles, " +
                   std::to_string(s.shell.quality.points_inside) + " of " + std::to_string(s.shell.points) +
                   " points inside>";
        });

    const snvr::ShellSettings shell_defaults;
    m.def("shell", &shell, py::arg("points"), py::kw_only(), py::arg("resolution") = py::none(),
          py::arg("voxel") = py::none(), py::arg("offset") = py::none(), py::arg("thickness") = py::none(),
          py::arg("offset_cells") = py::none(), py::arg("keep_outliers") = false, py::arg("origin") = "auto",
          py::arg("fairing") = snvr::MeshFairing{}.passes, py::arg("min_piece_volume") = 0.0,
          py::arg("keep_largest") = 0, py::arg("measure") = false, py::arg("smoothing") = py::none(),
          py::arg("dt_cells") = py::none(), py::arg("steps") = py::none(), py::arg("tube_inner") = py::none(),
          py::arg("tube_outer") = py::none(), py::arg("free_flow") = false, py::arg("points_as_given") = false, py::arg("eps_cells") = py::none(),
          py::arg("xi_cells") = py::none(), py::arg("tol") = py::none(), py::arg("max_cycles") = py::none(),
          py::arg("tile_cells") = 0, py::arg("tile_halo_cells") = py::none(), py::arg("max_memory") = py::none(), py::arg("temp_dir") = "", py::arg("precision") = "float", py::arg("device") = "auto", py::arg("written_as") = ".stl",
          py::arg("keep_field") = false, py::arg("units") = shell_defaults.units,
          py::arg("scale") = shell_defaults.scale, py::arg("progress") = py::none(),
          "The printable shell around points ((N, 3) array, lengths in their units; or a file's path, read as "
          "snvr-cl reads it, meshes sampled), as snvr-cl reconstruct makes it. Keywords are snvr-cl's options (resolution, voxel, offset, thickness, offset_cells, "
          "keep_outliers, origin, fairing, min_piece_volume, keep_largest, measure, smoothing, dt_cells, steps, "
          "tube_inner, tube_outer, free_flow, points_as_given, eps_cells, xi_cells, tol, max_cycles, tile_cells, tile_halo_cells, precision, device; max_memory in bytes, the memory the call may add: "
          "what it makes of the points and all after, not the caller's array); temp_dir: where a .gz file "
          "is inflated (default TMPDIR, else /tmp); "
          "written_as: the format the mesh is meant for ('.stl': float32). units ('mm', 'cm', 'm' or 'in') and scale: "
          "the points' unit and a factor on it, as snvr-cl's --units and --scale (the shell comes back in millimetres). progress(stage, step, steps) may "
          "return False to cancel (snvr.Cancelled); Ctrl-C cancels too (KeyboardInterrupt).");
    m.def("read_points", [](const std::string& path) -> py::array {
        snvr::detail::FloatPoints points;
        {
            py::gil_scoped_release unlocked;
            points = snvr::detail::read_float_points(path);
        }
        const py::ssize_t n = py::ssize_t(points.xyz.size());
        if (points.origin == snvr::Vec3{0, 0, 0}) {
            // The file's floats as they are: the reader's own buffer becomes the array (no
            // copy), and shell() files it exactly as snvr-cl files the file.
            using Coordinates = snvr::detail::PointArray<snvr::Vec3f>;
            auto* held = new Coordinates(std::move(points.xyz));
            const py::capsule owner(held, [](void* v) { delete static_cast<Coordinates*>(v); });
            return py::array_t<float>({n, py::ssize_t(3)}, held->empty() ? nullptr : held->front().data(), owner);
        }
        // Far from the world origin: float64 in world units (no PointSet between).
        py::array_t<double> out({n, py::ssize_t(3)});
        double* to = out.mutable_data();
        {
            py::gil_scoped_release unlocked;
            for (std::size_t i = 0; i < points.xyz.size(); ++i)
                for (int a = 0; a < 3; ++a) to[3 * i + std::size_t(a)] = points.origin[std::size_t(a)] + double(points.xyz[i][std::size_t(a)]);
        }
        return out;
    }, py::arg("path"), "The points of a file snvr-cl reads (.ply, .las, .xyz, .obj, .off, ... and .gz), (N, 3): float32 where "
          "float holds them as they are (no copy), else float64 in world units.");
}
