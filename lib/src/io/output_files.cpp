// OutputFiles: every output staged in full before any is renamed into place.
#include <memory>
#include <string>
#include <utility>

#include "io/atomic_file.hpp"
#include "io/staged_writes.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr {

OutputFiles::OutputFiles() = default;
OutputFiles::~OutputFiles() = default;  // uncommitted temporaries are removed here

std::uint64_t OutputFiles::add_mesh(const Mesh& mesh, const std::string& path) {
    files_.push_back(detail::stage_mesh(mesh, path));
    return files_.back()->bytes();
}

std::uint64_t OutputFiles::add_field(const Field& field, const Domain& domain, const std::string& path) {
    files_.push_back(detail::stage_field(field, domain, path));
    return files_.back()->bytes();
}

std::uint64_t OutputFiles::add_points(const PointSet& points, const std::string& path, const std::string& comment) {
    files_.push_back(detail::stage_points(points, path, comment));
    return files_.back()->bytes();
}

std::uint64_t OutputFiles::add_bytes(const std::string& bytes, const std::string& path) {
    auto file = std::make_unique<AtomicFile>(path);
    file->write(bytes);
    file->finish();
    files_.push_back(std::move(file));
    return files_.back()->bytes();
}

// Every temporary named beside its target and closed first: any failure there (a
// folder gone or read-only, a full disk) leaves every target as it was. Only the
// renames are left then; they fail only if a folder changes between two of them.
void OutputFiles::commit() {
    std::vector<std::unique_ptr<AtomicFile>> files = std::move(files_);
    for (auto& file : files) file->prepare();
    for (auto& file : files) file->commit();
}

}  // namespace snvr
