// InputSource: a file's bytes for its parser, read (never mapped) as it asks for them, and
// refused when the file changes meanwhile.
#include "io/input_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "io/formats.hpp"
#include "io/gunzip.hpp"
#include "io/io_common.hpp"
#include "process_limits.hpp"
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

}  // namespace

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
    // An open file of this process's own (a temporary), as it is now.
    OpenFile(int open_fd, const std::string& path) : fd(open_fd) {
        if (::fstat(fd, &opened) != 0) {
            const int err = errno;
            ::close(fd);
            throw IoError("cannot read '" + path + "': " + system_reason(err));
        }
        size = std::size_t(opened.st_size);
    }
    ~OpenFile() { ::close(fd); }
    OpenFile(const OpenFile&) = delete;
    OpenFile& operator=(const OpenFile&) = delete;
};

namespace {

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

}  // namespace

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

void require_regular_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw IoError("cannot open '" + path + "': " + system_reason(errno));
    require_regular(path, st);
}

std::string format_name(const std::string& path) {
    return lower_extension(path) == ".gz" ? path.substr(0, path.size() - 3) : path;
}

namespace {

// An unnamed file in `folder` for this process alone (Linux's O_TMPFILE: it goes with the
// process however it ends, SIGKILL included); where the file system has none, a named
// one removed at once. -1 with errno where neither can be made.
int unnamed_file(const std::string& folder) {
#ifdef O_TMPFILE
    const int fd = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd >= 0 || (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)) return fd;
#endif
    std::string name = folder + "/.snvr-inflated-XXXXXX";
    const int named = ::mkstemp(name.data());
    if (named >= 0) ::unlink(name.c_str());
    return named;
}

std::string temporary_folder(const std::string& given) {
    if (!given.empty()) return given;
    const char* tmp = std::getenv("TMPDIR");
    return tmp && *tmp ? tmp : "/tmp";
}

// Free bytes for this process in the folder's file system (0 where unknown).
std::uint64_t free_bytes(const std::string& folder) {
    struct statvfs fs {};
    if (::statvfs(folder.c_str(), &fs) != 0) return 0;
    return std::uint64_t(fs.f_bavail) * std::uint64_t(fs.f_frsize);
}

// What the last gzip member says it inflates to (its size mod 2^32): for a file of one
// member under 4 GiB, the size. 0 where the file is too short to say.
std::uint64_t stated_size(const OpenFile& file) {
    unsigned char tail[4];
    if (file.size < 18 || ::pread(file.fd, tail, 4, off_t(file.size - 4)) != 4) return 0;
    return std::uint64_t(tail[0]) | std::uint64_t(tail[1]) << 8 | std::uint64_t(tail[2]) << 16 |
           std::uint64_t(tail[3]) << 24;
}

}  // namespace

InputSource::InputSource(const std::string& path, const std::string& temp_folder)
    : path_(path), file_(std::make_unique<OpenFile>(path)), fault_(std::make_unique<ReadFault>()), size_(file_->size) {
    if (lower_extension(path) != ".gz") return;
    const auto look = [&path](std::string_view first) { require_signature(first, path); };
    // Inflated into an unnamed file in the temporary folder, a piece at a time (never whole
    // in memory: a PLY's records are then read in parts as from any file); where no such
    // file can be made there, into memory.
    const std::string folder = temporary_folder(temp_folder);
    const int fd = unnamed_file(folder);
    if (fd < 0 && !temp_folder.empty())
        throw IoError("cannot inflate '" + path + "' into the temporary folder '" + folder + "': " + system_reason(errno));
    if (fd < 0) {  // the system's folder unusable: as before, in memory
        const std::string_view packed = all();
        owned_ = gunzip(packed, path, look);
        PointArray<char>().swap(read_);
        file_.reset();
        memory_ = owned_;
        size_ = owned_.size();
        return;
    }
    auto inflated = std::make_unique<OpenFile>(fd, path);
    const std::uint64_t stated = stated_size(*file_), room = free_bytes(folder);
    const auto no_room = [&](std::uint64_t bytes, const std::string& why) {
        return IoError("cannot inflate '" + path + "' into the temporary folder '" + folder + "': " + why + " (" +
                       std::to_string(bytes) + " bytes; " + std::to_string(room) +
                       " free there); give a folder with room (--temp-dir)");
    };
    if (stated > 0 && room > 0 && stated > room) throw no_room(stated, "it inflates to more than is free");
    std::uint64_t read_at = 0, written = 0;
    gunzip_stream(
        file_->size,
        [&](char* to, std::size_t most) {
            if (!read_range(read_at, read_at + most, to)) finish();
            read_at += most;
            return most;
        },
        [&](std::string_view bytes) {
            for (std::size_t done = 0; done < bytes.size();) {
                const ssize_t n = ::pwrite(inflated->fd, bytes.data() + done, bytes.size() - done, off_t(written + done));
                if (n < 0 && errno == EINTR) continue;
                if (n < 0) throw no_room(written + done, system_reason(errno));
                done += std::size_t(n);
            }
            written += bytes.size();
        },
        path, look);
    finish();  // the compressed file as it was opened, read whole
    file_ = std::move(inflated);
    if (::fstat(file_->fd, &file_->opened) != 0) throw IoError("cannot read '" + path + "': " + system_reason(errno));
    file_->size = written;
    size_ = written;
}

InputSource::InputSource(std::string_view bytes, const std::string& path)
    : path_(path), memory_(bytes), size_(bytes.size()) {}

InputSource::~InputSource() = default;

void InputSource::skip_bom(bool skip) {
    constexpr std::string_view kBom = "\xEF\xBB\xBF";
    size_ += skip_;
    skip_ = 0;
    if (skip && size_ >= kBom.size() && head(kBom.size()) == kBom) {
        skip_ = kBom.size();
        size_ -= kBom.size();
    }
}

std::string_view InputSource::all() {
    if (memory_.data() == nullptr && size_ > 0) {
        try {
            read_.resize(file_->size);  // left unset: the read fills it
            advise_huge_pages(read_.data(), read_.size());
        } catch (const std::bad_alloc&) {
            throw ResourceError("cannot read '" + path_ + "': its " + std::to_string(file_->size) +
                                " bytes do not fit in memory");
        }
        read_whole(read_.data());
        memory_ = std::string_view(read_.data(), file_->size);
        finish();
    }
    return memory_.substr(std::min(skip_, memory_.size()));
}

std::string_view InputSource::head(std::size_t n) {
    n = std::min(n, size_);
    if (memory_.data() != nullptr || n == 0) return memory_.substr(std::min(skip_, memory_.size()), n);
    owned_.resize(n);
    if (!read_range(skip_, skip_ + n, owned_.data())) finish();
    return owned_;
}

bool InputSource::part(std::size_t begin, std::size_t end, std::vector<char>& buffer, std::string_view& bytes) const {
    if (!file_ || memory_.data() != nullptr) {
        bytes = memory_.substr(skip_ + begin, end - begin);
        return true;
    }
    if (buffer.size() < end - begin) buffer.resize(end - begin);
    bytes = std::string_view(buffer.data(), end - begin);
    return read_range(skip_ + begin, skip_ + end, buffer.data());
}

void InputSource::finish() const {
    if (failed_.load() != 0) throw IoError("cannot read '" + path_ + "': " + system_reason(failed_.load()));
    if (file_) require_unchanged(*file_, path_, !cut_short_.load());
}

// Bytes [begin, end) of the file, as it was opened, into `to`; false (noted for finish())
// where a read fails or the file ends first.
bool InputSource::read_range(std::size_t begin, std::size_t end, char* to) const {
    const auto failed = [this](int err) {  // the first errno met is the one named
        int none = 0;
        failed_.compare_exchange_strong(none, err);
        return false;
    };
    if (fault_->meet(path_, begin, end)) return failed(EIO);
    for (std::size_t at = begin; at < end;) {
        const ssize_t n = ::pread(file_->fd, to + (at - begin), end - at, off_t(at));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return failed(errno);
        if (n == 0) {
            cut_short_.store(true);  // require_unchanged names it
            return false;
        }
        at += std::size_t(n);
    }
    return true;
}

// The whole file into `to`, by the threads in 4 MiB parts where it is large.
void InputSource::read_whole(char* to) const {
    constexpr std::size_t kPart = std::size_t(4) << 20;
    const std::size_t size = file_->size, parts = (size + kPart - 1) / kPart;
    settle_threads();  // before the first parallel region: the OpenMP runtime cannot fail softly
#pragma omp parallel for schedule(dynamic, 1) if (parts > 4)
    for (std::ptrdiff_t p = 0; p < std::ptrdiff_t(parts); ++p) {
        const std::size_t begin = std::size_t(p) * kPart, end = std::min(size, begin + kPart);
        read_range(begin, end, to + begin);
    }
}

}  // namespace snvr::detail
