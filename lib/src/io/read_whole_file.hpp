// The whole of a file as bytes, read (in parallel parts where it is large) at the size it
// had when opened; a file that shrinks, grows or is rewritten meanwhile is refused.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

#include "large_array.hpp"

namespace snvr::detail {

// Throws IoError naming the file unless path names a regular file (following
// symbolic links): a directory, a named pipe, a device or a socket is refused
// by name, before any read that could block or never end.
void require_regular_file(const std::string& path);

// Throws IoError naming the file and the system's reason when it cannot be opened
// or read, or when it is not a regular file, and naming the change when another process
// cut it short, extended it or rewrote it while it was read.
std::string read_whole_file(const std::string& path);

// read_whole_file, inflated when the name ends in ".gz" (see format_name).
std::string read_input_bytes(const std::string& path);

// path without a trailing ".gz": the name whose extension picks the format.
std::string format_name(const std::string& path);

// The bytes read_input_bytes gives: a plain file read into storage left unset (no zeroing,
// huge pages where offered), a .gz file inflated into memory. Whichever, released by
// release() or the destructor, so that parsed points need not share memory with them.
// Throws as read_whole_file. (Not mapped: a mapped file cut short by another process ends
// the process with SIGBUS.)
class InputBytes {
public:
    explicit InputBytes(const std::string& path);
    ~InputBytes() { release(); }
    InputBytes(const InputBytes&) = delete;
    InputBytes& operator=(const InputBytes&) = delete;

    std::string_view view() const { return view_; }
    void release();

private:
    LargeArray<char> read_;  // a plain file's bytes
    std::string owned_;      // inflated
    std::string_view view_;
};

}  // namespace snvr::detail
