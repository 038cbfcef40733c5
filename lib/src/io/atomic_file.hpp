// Writes a file so that readers see either the old contents or the complete
// new ones: the data goes to a temporary next to the target (same directory,
// so the final rename cannot cross file systems) and commit() renames it onto
// the target. If commit() is never reached, or any step fails, the temporary
// is removed and the target is left as it was.
#pragma once
#include <cstddef>
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

    // Flushes, closes and renames onto the target; throws IoError on failure.
    void commit();

    const std::string& target() const { return target_; }

private:
    void flush_buffer();
    void discard() noexcept;
    [[noreturn]] void fail(const std::string& action, int err);

    std::string target_;
    std::string temp_;
    std::FILE* file_ = nullptr;
    std::vector<char> buffer_;
    bool committed_ = false;
};

}  // namespace snvr
