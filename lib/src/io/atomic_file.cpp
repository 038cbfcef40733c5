#include "io/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <unistd.h>
#include <utility>

#include "snvr/error.hpp"

namespace snvr {
namespace {

// Small records (50-byte STL triangles, OBJ lines) are gathered here so that
// each costs a memcpy rather than a locked fwrite.
constexpr std::size_t buffer_capacity = std::size_t(1) << 20;

// The pid keeps concurrent processes apart, the counter concurrent threads.
std::string temporary_name(const std::string& target) {
    static std::atomic<unsigned> counter{0};
    return target + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

// Some C libraries leave errno at 0 on a failed stream call.
int error_or_eio(int err) { return err != 0 ? err : EIO; }

}  // namespace

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)), temp_(temporary_name(target_)) {
    errno = 0;
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) throw IoError("cannot write '" + target_ + "': " + std::strerror(error_or_eio(errno)));
    buffer_.reserve(buffer_capacity);
}

AtomicFile::~AtomicFile() {
    if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
    if (file_) std::fclose(file_);
    file_ = nullptr;
    std::remove(temp_.c_str());
    committed_ = true;  // nothing left to clean up
}

void AtomicFile::fail(const std::string& action, int err) {
    discard();
    throw IoError("cannot " + action + " '" + target_ + "': " + std::strerror(error_or_eio(err)));
}

void AtomicFile::flush_buffer() {
    if (buffer_.empty()) return;
    errno = 0;
    if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) fail("write", errno);
    buffer_.clear();
}

void AtomicFile::write(const void* data, std::size_t size) {
    if (!file_) throw IoError("cannot write '" + target_ + "': file already closed");
    if (buffer_.size() + size > buffer_capacity) flush_buffer();
    if (size >= buffer_capacity) {
        errno = 0;
        if (std::fwrite(data, 1, size, file_) != size) fail("write", errno);
        return;
    }
    const char* bytes = static_cast<const char*>(data);
    buffer_.insert(buffer_.end(), bytes, bytes + size);
}

void AtomicFile::commit() {
    if (!file_) throw IoError("cannot write '" + target_ + "': file already closed");
    flush_buffer();
    errno = 0;
    if (std::fflush(file_) != 0) fail("write", errno);
    std::FILE* file = file_;
    file_ = nullptr;
    errno = 0;
    // A failing close (e.g. a full disk on NFS) means the data may be lost.
    if (std::fclose(file) != 0) fail("write", errno);
    errno = 0;
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) fail("rename temporary file onto", errno);
    committed_ = true;
}

}  // namespace snvr
