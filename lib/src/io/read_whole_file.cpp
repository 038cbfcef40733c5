// read_whole_file and InputBytes: one regular file into memory, for the readers that
// parse from memory.
#include "io/read_whole_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <string>

#include "io/formats.hpp"
#include "io/gunzip.hpp"
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

// A regular file open for reading, with the size it had when opened.
struct OpenFile {
    int fd = -1;
    std::size_t size = 0;

    explicit OpenFile(const std::string& path) {
        // O_NONBLOCK: opening a named pipe must not wait for a writer; the type is then
        // taken from the open file itself, whatever the path names by now.
        fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
        if (fd < 0) throw IoError("cannot open '" + path + "': " + system_reason(errno));
        struct stat st {};
        if (::fstat(fd, &st) != 0) {
            const int err = errno;
            ::close(fd);
            throw IoError("cannot read '" + path + "': " + system_reason(err));
        }
        if (!S_ISREG(st.st_mode)) {
            ::close(fd);
            require_regular(path, st);
        }
        size = std::size_t(st.st_size);
    }
    ~OpenFile() { ::close(fd); }
    OpenFile(const OpenFile&) = delete;
    OpenFile& operator=(const OpenFile&) = delete;
};

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
    std::size_t got = 0;
    while (got < data.size()) {
        const ssize_t n = ::read(file.fd, &data[got], data.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw IoError("cannot read '" + path + "': " + system_reason(errno));
        if (n == 0) break;  // shrunk since it was opened: what is there is all there is
        got += std::size_t(n);
    }
    data.resize(got);
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
    {
        const OpenFile file(path);
        if (file.size == 0) return;  // nothing to map (mmap refuses a length of 0)
        void* at = ::mmap(nullptr, file.size, PROT_READ, MAP_PRIVATE, file.fd, 0);
        if (at != MAP_FAILED) {
            mapped_ = at;
            mapped_size_ = file.size;
            ::madvise(at, file.size, MADV_WILLNEED);  // advice only: read ahead what is not cached
            view_ = std::string_view(static_cast<const char*>(at), file.size);
            return;
        }
    }
    owned_ = read_whole_file(path);  // a file system that cannot map
    view_ = owned_;
}

void InputBytes::release() {
    if (mapped_) ::munmap(mapped_, mapped_size_);
    mapped_ = nullptr;
    mapped_size_ = 0;
    std::string().swap(owned_);
    view_ = {};
}

}  // namespace snvr::detail
