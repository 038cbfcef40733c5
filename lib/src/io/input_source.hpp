// A file's bytes as its parser asks for them: a header, the whole, or the records part by
// part for each thread. A plain file is read, never mapped (a mapped file cut short by
// another process ends the process with SIGBUS), and refused when it shrinks, grows or is
// rewritten before its parser is done; a .gz file is inflated into an unnamed temporary
// file, a piece at a time.
#pragma once
#include <atomic>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "spilled_memory.hpp"

namespace snvr::detail {

// Throws IoError naming the file unless path names a regular file (following
// symbolic links): a directory, a named pipe, a device or a socket is refused
// by name, before any read that could block or never end.
void require_regular_file(const std::string& path);

// path without a trailing ".gz": the name whose extension picks the format.
std::string format_name(const std::string& path);

struct OpenFile;
struct ReadFault;

class InputSource {
public:
    // A file: a plain one opened (nothing read yet), a .gz one inflated (its first bytes
    // checked against its name's format) into an unnamed file in `temp_folder` (empty:
    // TMPDIR, else /tmp, and into memory where no file can be made there), read from
    // there as a plain one. Throws IoError naming the file and
    // the system's reason when it cannot be opened or read, or is not a regular file, or
    // the folder has no room for it inflated.
    explicit InputSource(const std::string& path, const std::string& temp_folder = {});
    // Bytes in memory, read as a file named path would be.
    InputSource(std::string_view bytes, const std::string& path);
    ~InputSource();
    InputSource(const InputSource&) = delete;
    InputSource& operator=(const InputSource&) = delete;

    const std::string& path() const { return path_; }
    // Bytes, less a skipped byte-order mark.
    std::size_t size() const { return size_; }
    // Skips a UTF-8 byte-order mark, as some Windows tools write before text (or, with
    // false, keeps it: a binary file may start with those bytes).
    void skip_bom(bool skip = true);

    // Every byte, read once (in parallel parts where large), checked as finish() checks.
    std::string_view all();
    // The first min(n, size()) bytes. Throws as finish() where the read falls short.
    std::string_view head(std::size_t n);
    // Bytes [begin, end), for one thread of many: a view of memory, or read from the file
    // into `buffer` (grown where it is smaller). False where the file ended early or a
    // read failed: finish() then throws, naming which.
    bool part(std::size_t begin, std::size_t end, std::vector<char>& buffer, std::string_view& bytes) const;
    // Throws IoError where a read failed or the file changed since it was opened (its size
    // and modification time are compared). Parsers that read parts call it when done.
    void finish() const;

private:
    bool read_range(std::size_t begin, std::size_t end, char* to) const;
    void read_whole(char* to) const;

    std::string path_;
    std::unique_ptr<OpenFile> file_;  // a plain file, open; null when the bytes are in memory
    std::unique_ptr<ReadFault> fault_;
    PointArray<char> read_;  // a plain file's bytes, once all() read them (a text file's: beyond a budget, in a file)
    std::string owned_;               // inflated, or a plain file's head
    std::string_view memory_;         // every byte, where they are in memory
    std::size_t skip_ = 0, size_ = 0;
    mutable std::atomic<int> failed_{0};          // the first errno a read met
    mutable std::atomic<bool> cut_short_{false};  // a read found the file ending early
};

}  // namespace snvr::detail
