// The format table (io/formats.hpp): every row's extensions reach its parsers and
// writers, the messages name what each use takes, one PLY header parser answers every
// PLY reader, and the CLI's help lists every extension the readers and writers take.
#include <doctest/doctest.h>

#include <cctype>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "io/formats.hpp"
#include "snvr/error.hpp"
#include "snvr/formats.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_io.hpp"
#include "snvr/shell.hpp"
#include "temp_dir.hpp"
#include "test_files.hpp"

using snvr::FormatUse;
using snvr::detail::Format;
using snvr::testing::TempDir;
using snvr::testing::write_bytes;

namespace {

const FormatUse kUses[] = {FormatUse::ReadPoints, FormatUse::ReadMesh, FormatUse::WriteMesh, FormatUse::WritePoints,
                           FormatUse::WriteField};

std::string upper(std::string text) {
    for (char& c : text) c = char(std::toupper(static_cast<unsigned char>(c)));
    return text;
}

// The message `action` throws as an InputError ("" when it throws none).
template <class F>
std::string input_error(F&& action) {
    try {
        action();
    } catch (const snvr::InputError& e) {
        return e.what();
    }
    return "";
}

snvr::Mesh tetrahedron() {
    snvr::Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.1, 0.2, 1.3}};
    mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    return mesh;
}

}  // namespace

TEST_CASE("formats: every row's extensions, in any case and gzipped for reading, route to its functions") {
    for (const Format& f : snvr::detail::formats()) {
        REQUIRE(!f.extensions.empty());
        for (const std::string_view ext : f.extensions) {
            const std::string name = "a" + std::string(ext);
            CAPTURE(name);
            CHECK(snvr::detail::format_of(name) == &f);
            CHECK(snvr::detail::format_of("a" + upper(std::string(ext))) == &f);
            CHECK(snvr::detail::read_format(name + ".gz") == &f);
            CHECK(snvr::detail::format_of(name + ".gz") == nullptr);  // writers take no .gz
            for (const FormatUse use : kUses) {
                if (!snvr::detail::serves(f, use)) {
                    CHECK(!input_error([&] { snvr::detail::format_for(name, use); }).empty());
                    continue;
                }
                const Format& found = snvr::detail::format_for(name, use);
                CHECK(&found == &f);
                const std::string listed = snvr::detail::extension_list(use, ", ");
                CHECK(listed.find(std::string(ext)) != std::string::npos);
            }
            if (f.read.points) CHECK(&snvr::detail::format_for(name + ".gz", FormatUse::ReadPoints) == &f);
        }
    }
}

TEST_CASE("formats: each writer's file reads back through the same row") {
    const TempDir dir("formats");
    const snvr::PointSet points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5}};
    for (const Format& f : snvr::detail::formats()) {
        const std::string path = dir.file("w" + std::string(f.extensions.front()));
        CAPTURE(path);
        if (f.write.mesh) {
            snvr::write_mesh(tetrahedron(), path);
            if (f.read.mesh) CHECK(snvr::read_mesh(path).triangles.size() == 4);
            if (f.read.mesh) CHECK(snvr::read_input(path, snvr::Parameters{}).triangles == 4);  // its faces decide
        }
        if (f.write.points) {
            snvr::write_points(points, path);
            REQUIRE(bool(f.read.points));
            CHECK(snvr::read_points(path).size() == points.size());
            CHECK(snvr::read_input(path, snvr::Parameters{}).triangles == 0);
        }
        if (f.write.field) {
            const snvr::Field field = snvr::Field::from_dense(2, 2, 2, std::vector<double>(8, 1.0), snvr::Precision::Single);
            snvr::Domain domain;
            domain.h = 1;
            domain.nx = domain.ny = domain.nz = 2;
            snvr::write_field(field, domain, path);
            CHECK(std::filesystem::file_size(path) > 8 * 4);
        }
    }
}

TEST_CASE("formats: the messages list what each use takes, as before the table") {
    const TempDir dir("formats");
    const std::string e57 = dir.file("p.e57");
    write_bytes(e57, "1 2 3\n");
    CHECK(input_error([&] { snvr::read_points(e57); }) ==
          e57 + ": unsupported point file extension '.e57' (supported: .ply, .xyz, .pts, .txt, .csv, .obj, .off, .las, "
                "each also gzipped as .gz)");
    CHECK(input_error([&] { snvr::read_mesh(e57); }) ==
          e57 + ": unsupported mesh file extension '.e57' (supported: .stl, .ply, .obj, .off)");
    const std::string laz = dir.file("p.laz");
    write_bytes(laz, "LASF");
    CHECK(input_error([&] { snvr::read_points(laz); }) ==
          laz + ": LAZ (compressed LAS) is not read; decompress it first, e.g. laszip -i " + laz + " -o points.las");
    CHECK(input_error([&] { snvr::write_mesh(tetrahedron(), "m.xyz"); }) ==
          "m.xyz: unsupported mesh file extension '.xyz' (supported: .stl, .ply, .obj, .3mf)");
    CHECK(input_error([&] { snvr::write_points({{0, 0, 0}}, "p.csv"); }) ==
          "p.csv: unsupported point file extension '.csv' (supported: .ply, .xyz, .pts, .txt)");
    // The signature of a gzipped file: its name's magic, else text, except STL.
    const std::string ply = dir.file("p.ply.gz"), las = dir.file("p.las.gz"), xyz = dir.file("p.xyz.gz");
    write_bytes(ply, snvr::testing::gzip("plx"));
    write_bytes(las, snvr::testing::gzip("LASX"));
    write_bytes(xyz, snvr::testing::gzip(std::string("1 2\0 3", 6)));
    CHECK(input_error([&] { snvr::read_points(ply); }) ==
          ply + ": the inflated data does not start as a PLY file ('ply') does");
    CHECK(input_error([&] { snvr::read_points(las); }) ==
          las + ": the inflated data does not start as a LAS file ('LASF') does");
    CHECK(input_error([&] { snvr::read_points(xyz); }) ==
          xyz + ": the inflated data does not start as text (it holds NUL bytes) does");
    CHECK(snvr::detail::is_print_format("a.STL"));
    CHECK(snvr::detail::is_print_format("a.3mf"));
    CHECK(!snvr::detail::is_print_format("a.ply"));
}

TEST_CASE("formats: one PLY header parser for points, meshes and the faces check") {
    const TempDir dir("formats");
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
    const std::string bad = dir.file("bad.ply");
    write_bytes(bad, head + "element face 1\nproperty list float int vertex_indices\nend_header\n" + vertices + "3 0 1 2\n");
    const std::string message = input_error([&] { snvr::read_points(bad); });
    CHECK(message.find("header line 8: list count type 'float' is not an integer type") != std::string::npos);
    CHECK(input_error([&] { snvr::read_mesh(bad); }) == message);
    CHECK(input_error([&] { snvr::read_input(bad, snvr::Parameters{}); }) == message);

    const std::string face = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string mesh = dir.file("mesh.ply"), points = dir.file("points.ply"), none = dir.file("none.ply");
    write_bytes(mesh, head + face + vertices + "3 0 1 2\n");
    write_bytes(points, head + "end_header\n" + vertices);
    write_bytes(none, head + "element face 0\nproperty list uchar int vertex_indices\nend_header\n" + vertices);
    CHECK(snvr::read_input(mesh, snvr::Parameters{}).triangles == 1);
    CHECK(snvr::read_input(points, snvr::Parameters{}).triangles == 0);
    CHECK(snvr::read_input(none, snvr::Parameters{}).triangles == 0);  // no face items: points
    CHECK(snvr::read_points(mesh).size() == 3);
    CHECK(snvr::read_mesh(mesh).triangles.size() == 1);
}

TEST_CASE("formats: the CLI's help lists every extension the readers and writers take") {
    const cli_testing::Run help = cli_testing::run("reconstruct --help");
    REQUIRE(help.code == 0);
    for (const Format& f : snvr::detail::formats())
        for (const std::string_view ext : f.extensions) {
            CAPTURE(ext);
            const bool listed = help.output.find(std::string(ext)) != std::string::npos;
            if (f.read.points || f.read.mesh || f.write.mesh || f.write.field) CHECK(listed);
        }
    CHECK(help.output.find(".gz") != std::string::npos);
    CHECK(help.output.find(snvr::format_extensions(FormatUse::ReadPoints)) != std::string::npos);
    CHECK(snvr::format_extensions(FormatUse::WriteField) == ".vti or .nrrd");
}
