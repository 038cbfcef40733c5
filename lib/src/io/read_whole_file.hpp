// The whole of a file as bytes, in one read of the size the file system gives.
#pragma once
#include <string>

namespace snvr::detail {

// Throws IoError naming the file unless path names a regular file (following
// symbolic links): a directory, a named pipe, a device or a socket is refused
// by name, before any read that could block or never end.
void require_regular_file(const std::string& path);

// Throws IoError naming the file and the system's reason when it cannot be opened
// or read, or when it is not a regular file. Reads no more than the size the file
// had when opened, so a file that grows meanwhile cannot keep it reading.
std::string read_whole_file(const std::string& path);

// read_whole_file, inflated when the name ends in ".gz" (see format_name).
std::string read_input_bytes(const std::string& path);

// path without a trailing ".gz": the name whose extension picks the format.
std::string format_name(const std::string& path);

}  // namespace snvr::detail
