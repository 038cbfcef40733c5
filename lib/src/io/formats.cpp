// The format table (formats.hpp): one row per format, and the look-ups every reader,
// writer and help text goes through.
#include "io/formats.hpp"

#include <algorithm>
#include <string>

#include "io/io_common.hpp"
#include "io/mesh_readers.hpp"
#include "io/input_source.hpp"
#include "io/writers.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

bool always(InputSource&, const std::string&) { return true; }

std::string laz_not_read(const std::string& path) {
    return "LAZ (compressed LAS) is not read; decompress it first, e.g. laszip -i " + path + " -o points.las";
}

// A row a format: name, extensions, signature {magic, any start},
// reading {points, mesh, faces, points not read},
// writing {mesh whole, points, field, stores, print, ns a triangle, mesh in parts}.
// STL first: the mesh readers' and writers' lists have always begun with it.
std::vector<Format> make_formats() {
    return {
        {"STL", {".stl"}, {"", true}, {nullptr, read_stl_mesh, always}, {nullptr, nullptr, nullptr, Stores::Float32, true, 30, stl_sink}},
        {"PLY", {".ply"}, {"ply"}, {parse_ply, read_ply_mesh, ply_has_faces}, {nullptr, write_ply_points, nullptr, Stores::Float32, false, 17, ply_sink}},
        {"text points", {".xyz", ".pts", ".txt"}, {}, {parse_xyz}, {nullptr, write_text_points}},
        {"CSV", {".csv"}, {}, {parse_xyz}, {}},  // never written: the text writer separates by spaces
        {"OBJ", {".obj"}, {}, {parse_obj, read_obj_mesh, obj_has_faces}, {nullptr, nullptr, nullptr, Stores::Exactly, false, 200, obj_sink}},
        {"OFF", {".off"}, {}, {parse_off, read_off_mesh, off_has_faces}, {}},
        {"LAS", {".las"}, {"LASF"}, {parse_las}, {}},
        {"LAZ", {".laz"}, {}, {nullptr, nullptr, nullptr, laz_not_read}, {}},
        {"3MF", {".3mf"}, {}, {}, {write_3mf, nullptr, nullptr, Stores::Float32SixDecimals, true, 2100}},
        {"VTI", {".vti"}, {}, {}, {nullptr, nullptr, write_vti}},
        {"NRRD", {".nrrd"}, {}, {}, {nullptr, nullptr, write_nrrd}},
    };
}

}  // namespace

const std::vector<Format>& formats() {
    static const std::vector<Format> table = make_formats();
    return table;
}

const Format* format_of(const std::string& path) {
    const std::string ext = lower_extension(path);
    for (const Format& f : formats())
        if (std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end()) return &f;
    return nullptr;
}

const Format* read_format(const std::string& path) { return format_of(format_name(path)); }

const Format& format_for(const std::string& path, FormatUse use) {
    const bool reading = use == FormatUse::ReadPoints || use == FormatUse::ReadMesh;
    const std::string name = reading ? format_name(path) : path;  // "a.xyz.gz" reads as .xyz
    const Format* format = format_of(name);
    if (format && serves(*format, use)) return *format;
    if (format && use == FormatUse::ReadPoints && format->read.points_not_read)
        throw InputError(path + ": " + format->read.points_not_read(path));
    const char* kind = use == FormatUse::ReadPoints || use == FormatUse::WritePoints ? "point"
                       : use == FormatUse::WriteField                                ? "field"
                                                                                     : "mesh";
    throw InputError(path + ": unsupported " + kind + " file extension '" + lower_extension(name) +
                     "' (supported: " + extension_list(use, ", ") +
                     (use == FormatUse::ReadPoints ? ", each also gzipped as .gz)" : ")"));
}

bool serves(const Format& format, FormatUse use) {
    switch (use) {
        case FormatUse::ReadPoints: return format.read.points != nullptr;
        case FormatUse::ReadMesh: return format.read.mesh != nullptr;
        case FormatUse::WriteMesh: return format.write.mesh || format.write.parts;
        case FormatUse::WritePoints: return format.write.points != nullptr;
        case FormatUse::WriteField: return format.write.field != nullptr;
    }
    return false;
}

std::string extension_list(FormatUse use, const char* last) {
    std::vector<std::string_view> all;
    for (const Format& f : formats())
        if (serves(f, use)) all.insert(all.end(), f.extensions.begin(), f.extensions.end());
    std::string list;
    for (std::size_t i = 0; i < all.size(); ++i)
        list += std::string(i == 0 ? "" : i + 1 == all.size() ? last : ", ") + std::string(all[i]);
    return list;
}

void require_signature(std::string_view first, const std::string& path) {
    const Format* format = read_format(path);
    const auto refuse = [&](const std::string& what) {
        throw InputError(path + ": the inflated data does not start as " + what + " does");
    };
    if (format && !format->signature.magic.empty()) {
        if (first.substr(0, format->signature.magic.size()) != format->signature.magic)
            refuse("a " + std::string(format->name) + " file ('" + std::string(format->signature.magic) + "')");
    } else if (!format || !format->signature.any_start) {
        if (first.find('\0') != std::string_view::npos) refuse("text (it holds NUL bytes)");
    }
}

bool is_print_format(const std::string& path) {
    const Format* format = format_of(path);
    return format && format->write.print;
}

double mesh_writing_seconds(const std::string& path, std::size_t triangles) {
    const Format* format = format_of(path);
    return format && (format->write.mesh || format->write.parts) ? format->write.ns_a_triangle * 1e-9 * double(triangles) : 0;
}

}  // namespace snvr::detail

namespace snvr {

std::string format_extensions(FormatUse use) { return detail::extension_list(use, " or "); }

bool format_serves(const std::string& path, FormatUse use) {
    const bool reading = use == FormatUse::ReadPoints || use == FormatUse::ReadMesh;
    const detail::Format* format = reading ? detail::read_format(path) : detail::format_of(path);
    return format && detail::serves(*format, use);
}

}  // namespace snvr
