// The whole of a file as bytes, in one read where the file system gives its size.
#pragma once
#include <string>

namespace snvr::detail {

// Throws IoError naming the file and the system's reason when it cannot be opened or read.
std::string read_whole_file(const std::string& path);

}  // namespace snvr::detail
