// Writes a file so that readers see either the old contents or the complete
// new ones. The data goes to an unnamed file in the target's directory (Linux's
// O_TMPFILE: a process killed even by SIGKILL leaves nothing behind) and commit()
// links it under a temporary name and renames that onto the target, so the
// final step cannot cross file systems. Where the file system has no unnamed
// files, a named temporary next to the target is used instead; while one exists
// it is listed for remove_temporary_files() (snvr/mesh_io.hpp), which a signal
// handler may call. If commit() is never reached, or any step fails, the
// temporary is removed and the target is left as it was.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace snvr {

class AtomicFile {
public:
    // Creates the temporary; throws IoError (naming the target) if it cannot.
    explicit AtomicFile(std::string target);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    // Buffered; throws IoError when a write to the temporary fails.
    void write(const void* data, std::size_t size);
    void write(std::string_view text) { write(text.data(), text.size()); }

    // Writes out everything buffered, so that commit() has only the rename left
    // to fail; throws IoError on failure (and removes the temporary).
    void finish();

    // finish(), then the temporary named beside the target and closed: only the rename
    // is left, which fails only if the folder changes meanwhile. Throws IoError.
    void prepare();
    // prepare(), then renames onto the target; throws IoError on failure.
    void commit();

    const std::string& target() const { return target_; }
    std::uint64_t bytes() const { return bytes_; }  // written so far

private:
    void flush_buffer();
    void discard() noexcept;
    [[noreturn]] void fail(const std::string& action, int err);
    void name_temporary();

    std::string target_;
    std::string temp_;  // empty while the file has no name
    std::FILE* file_ = nullptr;
    std::vector<char> buffer_;
    std::uint64_t bytes_ = 0;
    bool finished_ = false;
    bool prepared_ = false;
    bool committed_ = false;
};

}  // namespace snvr
