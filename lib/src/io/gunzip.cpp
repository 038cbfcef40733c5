#include "io/gunzip.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

struct Inflater {
    z_stream z{};
    bool open = false;
    ~Inflater() {
        if (open) inflateEnd(&z);
    }
};

// Deflate's largest expansion is 1032:1 (a run of 258 bytes in about two bits).
constexpr std::uint64_t kMaxRatio = 1032;
constexpr std::size_t kPiece = std::size_t(1) << 20;  // compressed bytes read, inflated bytes written, at a time

}  // namespace

void gunzip_stream(std::uint64_t size, const std::function<std::size_t(char*, std::size_t)>& read,
                   const std::function<void(std::string_view)>& write, const std::string& path,
                   const std::function<void(std::string_view first)>& look_first) {
    const auto fail = [&](const std::string& what, std::uint64_t at) -> InputError {
        return InputError(path + ": " + what + " (compressed byte offset " + std::to_string(at) + ")");
    };
    std::vector<char> in(std::size_t(std::min<std::uint64_t>(size, kPiece)) + 1), out(kPiece);
    std::uint64_t fed = 0;  // compressed bytes given to zlib
    const auto refill = [&](z_stream& z) {
        const std::size_t got = fed < size ? read(in.data(), std::size_t(std::min<std::uint64_t>(size - fed, kPiece))) : 0;
        if (got == 0 && fed < size) throw fail("the compressed file ends early", fed);
        z.next_in = reinterpret_cast<Bytef*>(in.data());
        z.avail_in = uInt(got);
        fed += got;
        return got;
    };
    Inflater inflater;
    z_stream& z = inflater.z;
    refill(z);
    if (z.avail_in < 2 || std::uint8_t(in[0]) != 0x1f || std::uint8_t(in[1]) != 0x8b)
        throw fail("not gzip data (no 1f 8b signature)", 0);
    // 16 + MAX_WBITS: gzip members only, with their headers and CRC checked.
    if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) throw ResourceError(path + ": zlib could not start");
    inflater.open = true;
    const std::uint64_t limit = kMaxRatio * size + 1024;
    std::uint64_t produced = 0;
    // The first bytes are held until look_first has seen them.
    std::string first;
    bool looked = !look_first;
    const auto emit = [&](std::string_view bytes) {
        if (looked) {
            if (!bytes.empty()) write(bytes);
            return;
        }
        first.append(bytes);
        if (first.size() < kFirstLookBytes) return;
        look_first(first);
        looked = true;
        write(first);
        std::string().swap(first);
    };
    for (;;) {
        z.next_out = reinterpret_cast<Bytef*>(out.data());
        z.avail_out = uInt(out.size());
        const int status = inflate(&z, Z_NO_FLUSH);
        const std::size_t made = out.size() - z.avail_out;
        produced += made;
        if (produced > limit) throw fail("decompresses beyond deflate's own bound: corrupt data", fed - z.avail_in);
        emit(std::string_view(out.data(), made));
        if (z.avail_in == 0 && fed < size) refill(z);
        const std::uint64_t at = fed - z.avail_in;
        if (status == Z_STREAM_END) {
            if (at == size) break;
            if (inflateReset(&z) != Z_OK) throw fail("a following gzip member cannot be read", at);
            continue;  // the next member of a concatenated file
        }
        if (status == Z_BUF_ERROR && z.avail_in == 0 && at == size) throw fail("the gzip data ends early", at);
        if (status != Z_OK && status != Z_BUF_ERROR)
            throw fail(std::string("corrupt gzip data") + (z.msg ? std::string(": ") + z.msg : std::string()), at);
    }
    if (!looked) {
        look_first(first);
        write(first);
    }
}

std::string gunzip(std::string_view data, const std::string& path,
                   const std::function<void(std::string_view first)>& look_first) {
    std::string out;
    std::size_t at = 0;
    gunzip_stream(
        data.size(),
        [&](char* to, std::size_t most) {
            const std::size_t n = std::min(most, data.size() - at);
            std::copy(data.data() + at, data.data() + at + n, to);
            at += n;
            return n;
        },
        [&](std::string_view bytes) { out.append(bytes); }, path, look_first);
    return out;
}

}  // namespace snvr::detail
