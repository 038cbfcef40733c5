// Input files the suites build byte by byte: gzip members and LAS point records.
#pragma once
#include <doctest/doctest.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace snvr::testing {

// `plain` as one gzip member.
inline std::string gzip(const std::string& plain) {
    std::string out(compressBound(uLong(plain.size())) + 64, '\0');
    z_stream z{};
    REQUIRE(deflateInit2(&z, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) == Z_OK);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(plain.data()));
    z.avail_in = uInt(plain.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = uInt(out.size());
    REQUIRE(deflate(&z, Z_FINISH) == Z_STREAM_END);
    out.resize(z.total_out);
    deflateEnd(&z);
    return out;
}

// Appends v's bytes, little endian as the host holds them.
template <class T>
void put_bytes(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    s.append(b, sizeof v);
}

// A LAS 1.2 file of point format 1 (28-byte records, the bytes after X, Y, Z filled with
// `fill`): each point stored as round((p - offset) / scale), the same scale and offset
// on every axis.
inline std::string las_file(const std::vector<std::array<double, 3>>& points, double scale, double offset,
                            char fill = '\0') {
    std::string s(227, '\0');
    s.replace(0, 4, "LASF");
    s[24] = 1;
    s[25] = 2;
    std::string h;
    put_bytes(h, std::uint16_t(227));
    put_bytes(h, std::uint32_t(227));
    s.replace(94, 6, h);
    s[104] = 1;
    h.clear();
    put_bytes(h, std::uint16_t(28));
    put_bytes(h, std::uint32_t(points.size()));
    s.replace(105, 6, h);
    h.clear();
    for (int a = 0; a < 3; ++a) put_bytes(h, scale);
    for (int a = 0; a < 3; ++a) put_bytes(h, offset);
    s.replace(131, 48, h);
    for (const auto& p : points) {
        std::string r;
        for (double x : p) put_bytes(r, std::int32_t(std::lround((x - offset) / scale)));
        r.resize(28, fill);
        s += r;
    }
    return s;
}

}  // namespace snvr::testing
