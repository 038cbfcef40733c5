#include "io/gunzip.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <string>

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

}  // namespace

std::string gunzip(std::string_view data, const std::string& path,
                   const std::function<void(std::string_view first)>& look_first) {
    const auto fail = [&](const std::string& what, std::uint64_t at) -> InputError {
        return InputError(path + ": " + what + " (compressed byte offset " + std::to_string(at) + ")");
    };
    if (data.size() < 2 || std::uint8_t(data[0]) != 0x1f || std::uint8_t(data[1]) != 0x8b)
        throw fail("not gzip data (no 1f 8b signature)", 0);
    Inflater in;
    // 16 + MAX_WBITS: gzip members only, with their headers and CRC checked.
    if (inflateInit2(&in.z, 16 + MAX_WBITS) != Z_OK) throw ResourceError(path + ": zlib could not start");
    in.open = true;
    in.z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    in.z.avail_in = uInt(std::min<std::size_t>(data.size(), UINT32_MAX));
    std::uint64_t fed = in.z.avail_in;
    const std::uint64_t limit = kMaxRatio * data.size() + 1024;
    std::string out;
    out.resize(std::min<std::uint64_t>(limit, std::max<std::uint64_t>(4 * data.size(), 1 << 16)));
    std::size_t produced = 0;
    bool looked = !look_first;
    for (;;) {
        if (!looked && produced >= kFirstLookBytes) {
            look_first(std::string_view(out.data(), produced));
            looked = true;
        }
        if (produced == out.size()) {
            if (out.size() >= limit) throw fail("decompresses beyond deflate's own bound: corrupt data", fed - in.z.avail_in);
            out.resize(std::min<std::uint64_t>(limit, 2 * out.size()));
        }
        in.z.next_out = reinterpret_cast<Bytef*>(&out[produced]);
        in.z.avail_out = uInt(std::min<std::size_t>(out.size() - produced, UINT32_MAX));
        const std::size_t room = in.z.avail_out;
        const int status = inflate(&in.z, Z_NO_FLUSH);
        produced += room - in.z.avail_out;
        if (in.z.avail_in == 0 && fed < data.size()) {  // inputs beyond 4 GiB come in pieces
            const std::size_t more = std::min<std::size_t>(data.size() - fed, UINT32_MAX);
            in.z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + fed));
            in.z.avail_in = uInt(more);
            fed += more;
        }
        const std::uint64_t at = fed - in.z.avail_in;
        if (status == Z_STREAM_END) {
            if (at == data.size()) break;
            if (inflateReset(&in.z) != Z_OK) throw fail("a following gzip member cannot be read", at);
            continue;  // the next member of a concatenated file
        }
        if (status == Z_BUF_ERROR && in.z.avail_in == 0 && at == data.size())
            throw fail("the gzip data ends early", at);
        if (status != Z_OK && status != Z_BUF_ERROR)
            throw fail(std::string("corrupt gzip data") + (in.z.msg ? std::string(": ") + in.z.msg : std::string()), at);
    }
    out.resize(produced);
    if (!looked) look_first(out);
    return out;
}

}  // namespace snvr::detail
