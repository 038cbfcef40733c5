// The whole of a file as bytes: read in one read of the size the file system gives, or
// mapped where a parser needs only to look at them.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

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

// The bytes read_input_bytes gives, without copying a plain file: it is mapped read-only
// (read whole where it cannot be mapped); a .gz file is inflated into memory. Whichever,
// released by release() or the destructor, so that parsed points need not share memory
// with them. Throws as read_whole_file. (Like any mapping, a file cut short by another
// process while mapped ends this one with SIGBUS; one that grows is read at its old size.)
class InputBytes {
public:
    explicit InputBytes(const std::string& path);
    ~InputBytes() { release(); }
    InputBytes(const InputBytes&) = delete;
    InputBytes& operator=(const InputBytes&) = delete;

    std::string_view view() const { return view_; }
    void release();

private:
    void* mapped_ = nullptr;
    std::size_t mapped_size_ = 0;
    std::string owned_;  // inflated, or read where mapping failed
    std::string_view view_;
};

}  // namespace snvr::detail
