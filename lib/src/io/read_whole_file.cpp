// read_whole_file: one file into memory, for the readers that parse from memory.
#include "io/read_whole_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};

}  // namespace

std::string read_whole_file(const std::string& path) {
    errno = 0;
    const std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw IoError("cannot open '" + path + "': " + std::strerror(errno != 0 ? errno : EIO));
    // Sized from the file system so a regular file takes one fread; the loop
    // still copes with files that grow or report no size.
    std::error_code ignored;
    const std::uintmax_t size = std::filesystem::file_size(path, ignored);
    std::size_t block = ignored ? std::size_t(1) << 20 : std::size_t(size) + 1;
    std::string data;
    for (;;) {
        const std::size_t old = data.size();
        data.resize(old + block);
        errno = 0;
        const std::size_t got = std::fread(&data[old], 1, block, file.get());
        data.resize(old + got);
        if (got < block) break;
        block = std::max(block, data.size());
    }
    if (std::ferror(file.get())) throw IoError("cannot read '" + path + "': " + std::strerror(errno != 0 ? errno : EIO));
    return data;
}

}  // namespace snvr::detail
