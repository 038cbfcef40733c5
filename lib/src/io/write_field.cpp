// write_field: VTK image data (.vti, raw appended binary) and NRRD (.nrrd),
// both placing samples at cell centres, both written atomically.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/formats.hpp"
#include "io/io_common.hpp"
#include "io/staged_writes.hpp"
#include "io/writers.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr {
namespace {

void validate_field(const Field& field, const Domain& domain, const std::string& path) {
    auto dims = [](int x, int y, int z) {
        return std::to_string(x) + "x" + std::to_string(y) + "x" + std::to_string(z);
    };
    if (field.nx != domain.nx || field.ny != domain.ny || field.nz != domain.nz)
        throw InputError(path + ": field is " + dims(field.nx, field.ny, field.nz) + " but the domain is " +
                         dims(domain.nx, domain.ny, domain.nz));
    if (field.nx <= 0 || field.ny <= 0 || field.nz <= 0) throw InputError(path + ": field has no cells");
    field.validate(path + ": ");
}

std::size_t sample_bytes(const Field& field) {
    return field.precision == Precision::Double ? sizeof(double) : sizeof(float);
}

// "a<sep>b<sep>c" with each number written exactly.
std::string triple(const Vec3& v, const char* separator) {
    return detail::format_number(v[0]) + separator + detail::format_number(v[1]) + separator +
           detail::format_number(v[2]);
}

// Every sample, x fastest, little-endian, a row of the grid at a time (a band field is
// never made dense whole).
template <typename T>
void write_le_samples(const Field& field, const std::vector<T>& stored, AtomicFile& out) {
    std::vector<T> row(std::size_t(field.nx));
    std::vector<char> bytes(row.size() * sizeof(T));
    for (int k = 0; k < field.nz; ++k)
        for (int j = 0; j < field.ny; ++j) {
            for (int i = 0; i < field.nx; ++i) row[std::size_t(i)] = stored[field.position(i, j, k)];
            for (std::size_t i = 0; i < row.size(); ++i) detail::store_le(row[i], &bytes[i * sizeof(T)]);
            out.write(bytes.data(), bytes.size());
        }
}

void write_samples(const Field& field, AtomicFile& out) {
    if (field.precision == Precision::Double)
        write_le_samples(field, field.stored_f64(), out);
    else
        write_le_samples(field, field.stored_f32(), out);
}

}  // namespace

void detail::write_vti(const Field& field, const Domain& domain, AtomicFile& out) {
    const Vec3 origin = domain.cell_center(0, 0, 0);
    const std::string extent = "0 " + std::to_string(field.nx - 1) + " 0 " + std::to_string(field.ny - 1) + " 0 " +
                               std::to_string(field.nz - 1);
    const std::string type = field.precision == Precision::Double ? "Float64" : "Float32";
    out.write("<?xml version=\"1.0\"?>\n"
              "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
              "  <ImageData WholeExtent=\"" + extent + "\" Origin=\"" + triple(origin, " ") + "\" Spacing=\"" +
              triple({domain.h, domain.h, domain.h}, " ") + "\">\n"
              "    <Piece Extent=\"" + extent + "\">\n"
              "      <PointData Scalars=\"phi\">\n"
              "        <DataArray type=\"" + type + "\" Name=\"phi\" format=\"appended\" offset=\"0\"/>\n"
              "      </PointData>\n"
              "    </Piece>\n"
              "  </ImageData>\n"
              "  <AppendedData encoding=\"raw\">\n"
              "   _");
    // The appended block is its byte count (header_type UInt64), then the samples.
    char count[8];
    detail::store_le(std::uint64_t(field.size() * sample_bytes(field)), count);
    out.write(count, sizeof count);
    write_samples(field, out);
    out.write("\n  </AppendedData>\n</VTKFile>\n");
}

void detail::write_nrrd(const Field& field, const Domain& domain, AtomicFile& out) {
    // NRRD's space origin is the centre of the first sample, as here.
    const Vec3 origin = domain.cell_center(0, 0, 0);
    const double h = domain.h;
    out.write(std::string("NRRD0004\n# written by libsnvr\ntype: ") +
              (field.precision == Precision::Double ? "double" : "float") + "\ndimension: 3\nsizes: " +
              std::to_string(field.nx) + " " + std::to_string(field.ny) + " " + std::to_string(field.nz) +
              "\nspace dimension: 3\nspace directions: (" + triple({h, 0, 0}, ",") + ") (" + triple({0, h, 0}, ",") +
              ") (" + triple({0, 0, h}, ",") + ")\nspace origin: (" + triple(origin, ",") +
              ")\nencoding: raw\nendian: little\n\n");
    write_samples(field, out);
}

std::unique_ptr<AtomicFile> detail::stage_field(const Field& field, const Domain& domain, const std::string& path) {
    const detail::FieldWriter write = detail::format_for(path, FormatUse::WriteField).write.field;
    validate_field(field, domain, path);
    auto out = std::make_unique<AtomicFile>(path);
    write(field, domain, *out);
    out->finish();
    return out;
}

void write_field(const Field& field, const Domain& domain, const std::string& path) {
    detail::stage_field(field, domain, path)->commit();
}

}  // namespace snvr
