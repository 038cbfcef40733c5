// read_whole_file and InputBytes: one regular file into memory, for the readers that
// parse from memory; read, not mapped, and refused when it changes meanwhile.
#include "io/read_whole_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <new>
#include <cstring>
#include <exception>
#include <string>

#include "io/formats.hpp"
#include "io/gunzip.hpp"
#include "process_limits.hpp"
#include "io/io_common.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

std::string system_reason(int err) { return std::strerror(err != 0 ? err : EIO); }

// What a path names when it is not a regular file, for the message.
const char* kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a named pipe";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

void require_regular(const std::string& path, const struct stat& st) {
    if (!S_ISREG(st.st_mode))
        throw IoError("cannot read '" + path + "': it is " + kind_of(st.st_mode) + ", not a regular file");
}

// A regular file open for reading, as it was when opened.
struct OpenFile {
    int fd = -1;
    std::size_t size = 0;
    struct stat opened {};

    explicit OpenFile(const std::string& path) {
        // O_NONBLOCK: opening a named pipe must not wait for a writer; the type is then
        // taken from the open file itself, whatever the path names by now.
        fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
        if (fd < 0) throw IoError("cannot open '" + path + "': " + system_reason(errno));
        if (::fstat(fd, &opened) != 0) {
            const int err = errno;
            ::close(fd);
            throw IoError("cannot read '" + path + "': " + system_reason(err));
        }
        if (!S_ISREG(opened.st_mode)) {
            ::close(fd);
            require_regular(path, opened);
        }
        size = std::size_t(opened.st_size);
    }
    ~OpenFile() { ::close(fd); }
    OpenFile(const OpenFile&) = delete;
    OpenFile& operator=(const OpenFile&) = delete;
};

// A file that another process cuts short, extends or rewrites while it is read (a
// scanner or a copy still writing it) is refused, naming the change: its size and
// modification time after the read must be those it had when opened.
void require_unchanged(const OpenFile& file, const std::string& path, bool read_whole) {
    struct stat now {};
    if (::fstat(file.fd, &now) != 0) throw IoError("cannot read '" + path + "': " + system_reason(errno));
    const std::size_t size = std::size_t(now.st_size);
    const bool same_time = now.st_mtim.tv_sec == file.opened.st_mtim.tv_sec &&
                           now.st_mtim.tv_nsec == file.opened.st_mtim.tv_nsec;
    if (size == file.size && same_time && read_whole) return;
    const std::string how = size < file.size   ? "it shrank from " + std::to_string(file.size) + " to " + std::to_string(size) + " bytes"
                            : size > file.size ? "it grew from " + std::to_string(file.size) + " to " + std::to_string(size) + " bytes"
                                               : "it was rewritten";
    throw IoError(path + ": the file changed while it was read (" + how + "); read it once it is complete");
}

// For tests only: SNVR_TEST_READ_FAULT=shrink:K, grow:K or eio:K makes the read of the
// byte at offset K meet what another process or a failing disk would do there: the file
// truncated to K bytes, 4096 bytes appended to it, or the read failing with EIO. Real
// truncation and growth, on the file itself, at a chosen place instead of a chosen time.
struct ReadFault {
    enum Kind { None, Shrink, Grow, Eio } kind = None;
    std::size_t at = 0;
    std::atomic<bool> fired{false};

    ReadFault() {
        const char* text = std::getenv("SNVR_TEST_READ_FAULT");
        if (!text) return;
        const std::string spec = text;
        const std::size_t colon = spec.find(':');
        if (colon == std::string::npos) return;
        const std::string name = spec.substr(0, colon);
        kind = name == "shrink" ? Shrink : name == "grow" ? Grow : name == "eio" ? Eio : None;
        at = std::size_t(std::strtoull(spec.c_str() + colon + 1, nullptr, 10));
    }
    // Whether the read of [begin, end) meets the fault: it happens then (once), and true
    // means the read itself fails with EIO.
    bool meet(const std::string& path, std::size_t begin, std::size_t end) {
        if (kind == None || at < begin || at >= end || fired.exchange(true)) return false;
        if (kind == Shrink) {
            if (::truncate(path.c_str(), off_t(at)) != 0) return false;
        } else if (kind == Grow) {
            const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
            if (fd >= 0) {
                const std::string more(4096, '\n');
                [[maybe_unused]] const ssize_t n = ::write(fd, more.data(), more.size());
                ::close(fd);
            }
        }
        return kind == Eio;
    }
};

// Reads the file's bytes as it was opened into `to` (file.size of them), in parallel
// parts where it is large, then refuses it if it changed meanwhile. No mapping: a file
// cut short while mapped ends the process with SIGBUS, and a library must not.
void read_all(const OpenFile& file, const std::string& path, char* to) {
    constexpr std::size_t kPart = std::size_t(4) << 20;
    const std::size_t parts = (file.size + kPart - 1) / kPart;
    ReadFault fault;
    std::atomic<int> failed{0};            // the first errno met
    std::atomic<bool> cut_short{false};    // a part found the file ending early
    const auto fail = [&failed](int err) {
        int none = 0;
        failed.compare_exchange_strong(none, err);
    };
    const auto read_part = [&](std::size_t p) {
        const std::size_t begin = p * kPart, end = std::min(file.size, begin + kPart);
        if (fault.meet(path, begin, end)) return fail(EIO);
        for (std::size_t at = begin; at < end;) {
            const ssize_t n = ::pread(file.fd, to + at, end - at, off_t(at));
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) return fail(errno);
            if (n == 0) return cut_short.store(true);  // require_unchanged names it
            at += std::size_t(n);
        }
    };
    settle_threads();  // before the first parallel region: the OpenMP runtime cannot fail softly
    const bool parallel = parts > 4;
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
    for (std::ptrdiff_t p = 0; p < std::ptrdiff_t(parts); ++p) read_part(std::size_t(p));
    if (failed.load() != 0) throw IoError("cannot read '" + path + "': " + system_reason(failed.load()));
    require_unchanged(file, path, !cut_short.load());
}

}  // namespace

void require_regular_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw IoError("cannot open '" + path + "': " + system_reason(errno));
    require_regular(path, st);
}

std::string read_whole_file(const std::string& path) {
    const OpenFile file(path);
    std::string data;
    try {
        data.resize(file.size);
    } catch (const std::exception&) {  // length_error or bad_alloc
        throw ResourceError("cannot read '" + path + "': its " + std::to_string(file.size) +
                            " bytes do not fit in memory");
    }
    read_all(file, path, data.data());
    return data;
}

std::string format_name(const std::string& path) {
    return lower_extension(path) == ".gz" ? path.substr(0, path.size() - 3) : path;
}

std::string read_input_bytes(const std::string& path) {
    std::string data = read_whole_file(path);
    if (lower_extension(path) != ".gz") return data;
    return gunzip(data, path, [&path](std::string_view first) { require_signature(first, path); });
}

InputBytes::InputBytes(const std::string& path) {
    if (lower_extension(path) == ".gz") {
        owned_ = read_input_bytes(path);
        view_ = owned_;
        return;
    }
    const OpenFile file(path);
    if (file.size == 0) return;
    try {
        read_ = large_array<char>(file.size);  // left unset: the read fills it
    } catch (const std::bad_alloc&) {
        throw ResourceError("cannot read '" + path + "': its " + std::to_string(file.size) +
                            " bytes do not fit in memory");
    }
    read_all(file, path, read_.get());
    view_ = std::string_view(read_.get(), file.size);
}

void InputBytes::release() {
    read_.reset();
    std::string().swap(owned_);
    view_ = {};
}

}  // namespace snvr::detail
