#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <utility>

#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr {
namespace {

// Small records (50-byte STL triangles, OBJ lines) are gathered here so that
// each costs a memcpy rather than a locked fwrite.
constexpr std::size_t buffer_capacity = std::size_t(1) << 20;

// The named temporaries that exist now, for remove_temporary_files(). Lock-free
// slots, so that a signal handler may read them while a thread changes them.
constexpr int kListed = 64;
std::atomic<char*> listed[kListed];

// Lists a copy of path; -1 when every slot is taken (the file then works as
// before, only a signal would leave it behind).
int list_temporary(const std::string& path) {
    char* copy = ::strdup(path.c_str());
    if (!copy) return -1;
    for (int s = 0; s < kListed; ++s) {
        char* expected = nullptr;
        if (listed[s].compare_exchange_strong(expected, copy)) return s;
    }
    std::free(copy);
    return -1;
}

void unlist_temporary(const std::string& path) {
    for (auto& slot : listed) {
        char* p = slot.load();
        if (p && path == p && slot.compare_exchange_strong(p, nullptr)) {
            std::free(p);
            return;
        }
    }
}

// The pid keeps concurrent processes apart, the counter concurrent threads.
std::string temporary_name(const std::string& target) {
    static std::atomic<unsigned> counter{0};
    return target + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

// Some C libraries leave errno at 0 on a failed stream call.
int error_or_eio(int err) { return err != 0 ? err : EIO; }

std::string directory_of(const std::string& target) {
    const std::string dir = std::filesystem::path(target).parent_path().string();
    return dir.empty() ? "." : dir;
}

// An unnamed file in dir, or -1 with errno set. Naming it later needs /proc.
int open_unnamed(const std::string& dir) {
#ifdef O_TMPFILE
    if (::access("/proc/self/fd", X_OK) != 0) {
        errno = EOPNOTSUPP;
        return -1;
    }
    return ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
#else
    (void)dir;
    errno = EOPNOTSUPP;
    return -1;
#endif
}

// The errors by which a kernel or file system says it has no unnamed files.
bool no_unnamed_files(int err) { return err == EOPNOTSUPP || err == EISDIR || err == EINVAL; }

}  // namespace

void remove_temporary_files() noexcept {
    for (auto& slot : listed)
        if (char* p = slot.exchange(nullptr)) ::unlink(p);  // not freed: a handler may not call free
}

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)) {
    errno = 0;
    int fd = open_unnamed(directory_of(target_));
    if (fd < 0 && no_unnamed_files(errno)) {
        temp_ = temporary_name(target_);
        list_temporary(temp_);
        fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) {
            const int err = errno;
            unlist_temporary(temp_);
            temp_.clear();
            errno = err;
        }
    }
    if (fd >= 0) file_ = ::fdopen(fd, "wb");
    if (!file_) {
        const int err = error_or_eio(errno);
        if (fd >= 0) ::close(fd);
        if (!temp_.empty()) {
            ::unlink(temp_.c_str());
            unlist_temporary(temp_);
        }
        throw IoError("cannot write '" + target_ + "': " + std::strerror(err));
    }
    buffer_.reserve(buffer_capacity);
}

AtomicFile::~AtomicFile() {
    if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
    if (file_) std::fclose(file_);
    file_ = nullptr;
    if (!temp_.empty()) {
        std::remove(temp_.c_str());
        unlist_temporary(temp_);
        temp_.clear();
    }
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
    if (!file_ || finished_) throw IoError("cannot write '" + target_ + "': file already closed");
    bytes_ += size;
    if (buffer_.size() + size > buffer_capacity) flush_buffer();
    if (size >= buffer_capacity) {
        errno = 0;
        if (std::fwrite(data, 1, size, file_) != size) fail("write", errno);
        return;
    }
    const char* bytes = static_cast<const char*>(data);
    buffer_.insert(buffer_.end(), bytes, bytes + size);
}

void AtomicFile::finish() {
    if (!file_) throw IoError("cannot write '" + target_ + "': file already closed");
    if (finished_) return;
    flush_buffer();
    errno = 0;
    if (std::fflush(file_) != 0) fail("write", errno);
    finished_ = true;
}

// Gives the unnamed file a name next to the target (listed first, so that a
// signal in between still finds it).
void AtomicFile::name_temporary() {
    const std::string fd_path = "/proc/self/fd/" + std::to_string(::fileno(file_));
    for (int attempt = 0;; ++attempt) {
        temp_ = temporary_name(target_);
        list_temporary(temp_);
        if (::linkat(AT_FDCWD, fd_path.c_str(), AT_FDCWD, temp_.c_str(), AT_SYMLINK_FOLLOW) == 0) return;
        const int err = errno;
        unlist_temporary(temp_);
        temp_.clear();
        if (err != EEXIST || attempt == 8) fail("write", err);
    }
}

void AtomicFile::prepare() {
    if (prepared_) return;
    finish();
    if (temp_.empty()) name_temporary();
    std::FILE* file = file_;
    file_ = nullptr;
    errno = 0;
    // A failing close (e.g. a full disk on NFS) means the data may be lost.
    if (std::fclose(file) != 0) fail("write", errno);
    prepared_ = true;
}

void AtomicFile::commit() {
    prepare();
    errno = 0;
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) fail("rename temporary file onto", errno);
    unlist_temporary(temp_);
    temp_.clear();
    committed_ = true;
}

}  // namespace snvr
