// gzip-compressed input (.ply.gz, .xyz.gz, ...), inflated in memory with zlib.
#pragma once
#include <string>
#include <string_view>

namespace snvr::detail {

// The concatenated contents of every gzip member in `data`. Throws InputError naming
// the file and the byte offset when the data is not gzip or is cut short. Deflate
// cannot expand beyond about 1032:1, so the output is bounded by the input's size.
std::string gunzip(std::string_view data, const std::string& path);

}  // namespace snvr::detail
