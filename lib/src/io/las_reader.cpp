// LAS 1.0-1.4 point clouds (ASPRS LiDAR format), uncompressed point records of any
// format 0-10: every record starts with X, Y, Z as int32, scaled and offset by the
// header's doubles. Compressed LAZ is refused by name. Only the header is read whole; the
// records are read part by part by the threads; the header's box chooses the origin.
#include <cmath>
#include <cstdint>
#include <string>

#include "io/float_origin.hpp"
#include "io/input_source.hpp"
#include "io/io_common.hpp"
#include "io/parallel_records.hpp"
#include "io/point_readers.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

// Byte offsets in the public header block.
constexpr std::size_t kVersionMajor = 24, kVersionMinor = 25, kHeaderSize = 94, kPointOffset = 96,
                      kPointFormat = 104, kRecordLength = 105, kLegacyCount = 107, kScale = 131, kOffset = 155,
                      kMaxX = 179, kCount64 = 247, kHeader12 = 227, kHeader14 = 375;

// The smallest record of each point data format 0-10.
constexpr std::uint16_t kRecordBytes[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

template <typename T>
T field(std::string_view data, std::size_t at) {
    return load_bytes<T>(data.data() + at, !host_is_little_endian());  // LAS is little endian
}

// A point record's X, Y, Z: int32 scaled and offset by the header's doubles.
struct LasPoint {
    double scale[3] = {}, offset[3] = {};

    Vec3 operator()(const char* record) const {
        Vec3 p;
        for (std::size_t a = 0; a < 3; ++a)
            p[a] = double(load_bytes<std::int32_t>(record + 4 * a, !host_is_little_endian())) * scale[a] + offset[a];
        return p;
    }
};

// The points' box as the header gives it (max before min, x, y, z); empty when the six
// figures make no box.
SampleBox header_box(std::string_view data) {
    SampleBox box;
    Vec3 lo, hi;
    for (std::size_t a = 0; a < 3; ++a) {
        hi[a] = field<double>(data, kMaxX + 16 * a);
        lo[a] = field<double>(data, kMaxX + 16 * a + 8);
        if (!(lo[a] <= hi[a])) return box;  // NaN fails too
    }
    box.add(lo);
    box.add(hi);
    return box;
}

}  // namespace

FloatPoints parse_las(InputSource& source, const std::string& path, const ParseOptions& options) {
    const auto fail = [&](const std::string& what) { return InputError(path + ": " + what); };
    const std::string_view data = source.head(kHeader14);  // the records are read part by part
    if (data.size() < 4 || data.substr(0, 4) != "LASF") throw fail("not a LAS file (no 'LASF' signature)");
    if (data.size() < kHeader12) throw fail("the LAS header is cut short (" + std::to_string(data.size()) + " bytes)");
    const std::size_t file_size = source.size();
    const int major = field<std::uint8_t>(data, kVersionMajor), minor = field<std::uint8_t>(data, kVersionMinor);
    const std::string version = std::to_string(major) + "." + std::to_string(minor);
    if (major != 1 || minor > 4) throw fail("LAS version " + version + " (readable: 1.0 to 1.4)");
    const std::uint16_t header = field<std::uint16_t>(data, kHeaderSize);
    const std::uint32_t first = field<std::uint32_t>(data, kPointOffset);
    const std::uint8_t format_byte = field<std::uint8_t>(data, kPointFormat);
    const std::uint16_t length = field<std::uint16_t>(data, kRecordLength);
    if (format_byte & 0xC0)
        throw fail("compressed point records (LAZ) are not read; decompress first, e.g. laszip -i in.laz -o out.las");
    if (format_byte > 10) throw fail("unknown point data format " + std::to_string(format_byte) + " (known: 0 to 10)");
    if (length < kRecordBytes[format_byte])
        throw fail("point records of " + std::to_string(length) + " bytes, but format " + std::to_string(format_byte) +
                   " needs at least " + std::to_string(kRecordBytes[format_byte]));
    std::uint64_t count = field<std::uint32_t>(data, kLegacyCount);
    if (count == 0 && minor >= 4 && header >= kHeader14 && file_size >= kHeader14)
        count = field<std::uint64_t>(data, kCount64);  // formats 6-10 may leave the legacy count 0
    if (first < header || first > file_size)
        throw fail("the point data offset " + std::to_string(first) + " lies outside the file (" +
                   std::to_string(file_size) + " bytes, header " + std::to_string(header) + ")");
    const std::uint64_t fit = (file_size - first) / length;
    if (count > fit)
        throw fail("expected " + std::to_string(count) + " point records, file ends after " + std::to_string(fit) +
                   " (byte offset " + std::to_string(first + fit * length) + ")");
    const RecordSpan records{first, length, std::size_t(count)};
    LasPoint decode;
    for (std::size_t a = 0; a < 3; ++a) {
        decode.scale[a] = field<double>(data, kScale + 8 * a);
        decode.offset[a] = field<double>(data, kOffset + 8 * a);
        // Zero, subnormal or non-finite, every coordinate would collapse or overflow.
        if (!std::isnormal(decode.scale[a]) || !std::isfinite(decode.offset[a]))
            throw fail(std::string("the header's ") + "xyz"[a] + " scale " + format_number(decode.scale[a]) +
                       " and offset " + format_number(decode.offset[a]) +
                       " make no coordinates (a scale is a normal number such as 0.001, an offset finite)");
    }
    const std::size_t n = records.count;
    FloatPoints points;
    // The header knows the box before any point is read; where it does not hold the
    // points to the bound (a header box that is wrong), the first points choose instead.
    const SampleBox claimed = header_box(data);
    const auto sampled = [&] { return sample_records(source, records, decode, options.origin_sample); };
    points.origin = choose_origin(claimed.count ? claimed : sampled());
    ConvertedRecords done = convert_records(source, records, decode, points.origin, points.xyz, options);
    if (claimed.count && (done.first_refused < n || !within_origin_bound(done.box, points.origin))) {
        points.origin = choose_origin(sampled());
        done = convert_records(source, records, decode, points.origin, points.xyz, options);
    }
    if (done.first_refused < n)
        refuse_point(path, done.first_refused, record_point(source, records, decode, done.first_refused), points.origin);
    return points;
}

}  // namespace snvr::detail
