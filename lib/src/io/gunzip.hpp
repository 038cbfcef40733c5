// gzip-compressed input (.ply.gz, .xyz.gz, ...), inflated with zlib: in pieces to where the
// caller puts them (input_source.cpp: an unnamed temporary file), or into memory.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace snvr::detail {

// The concatenated contents of every gzip member in `data`. Throws InputError naming
// the file and the byte offset when the data is not gzip or is cut short. Deflate
// cannot expand beyond about 1032:1, so the output is bounded by the input's size.
// `look_first`, when given, sees the first 64 KiB inflated (or all, if less) before the
// rest is inflated, and may throw: a file whose content is not what its name says
// (a bomb of zeros, say) is refused at once, not after inflating gigabytes.
constexpr std::size_t kFirstLookBytes = 1 << 16;
std::string gunzip(std::string_view data, const std::string& path,
                   const std::function<void(std::string_view first)>& look_first = {});
// The same over `size` compressed bytes that read(to, most) gives in pieces (each call at
// most `most`, 0 only at the end; it throws where the file fails), the inflated bytes to
// write() as they come (look_first's before any).
void gunzip_stream(std::uint64_t size, const std::function<std::size_t(char* to, std::size_t most)>& read,
                   const std::function<void(std::string_view)>& write, const std::string& path,
                   const std::function<void(std::string_view first)>& look_first = {});

}  // namespace snvr::detail
