// A fresh directory per test, removed with everything in it afterwards.
#pragma once
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

namespace snvr::testing {

struct TempDir {
    std::filesystem::path path;
    // `suite` names the directory (snvr-test-<suite>-...), so a leftover shows whose it is.
    explicit TempDir(const std::string& suite) {
        static std::atomic<unsigned> counter{0};
        std::random_device entropy;
        path = std::filesystem::temp_directory_path() /
               ("snvr-test-" + suite + "-" + std::to_string(entropy()) + "-" + std::to_string(counter++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
    std::size_t entries() const {
        return std::size_t(std::distance(std::filesystem::directory_iterator(path), std::filesystem::directory_iterator()));
    }
};

// Writes `bytes` to `path` as they are; throws (failing the test) when it cannot.
inline void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out.good()) throw std::runtime_error("cannot write " + path);
}

}  // namespace snvr::testing
