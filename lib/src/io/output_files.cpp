// OutputFiles: every output staged in full before any is renamed into place.
#include <memory>
#include <string>
#include <utility>

#include "io/atomic_file.hpp"
#include "io/formats.hpp"
#include "io/staged_writes.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr {

OutputFiles::OutputFiles() = default;
OutputFiles::~OutputFiles() = default;  // uncommitted temporaries are removed here

std::uint64_t OutputFiles::add_mesh(const Mesh& mesh, const std::string& path) {
    files_.push_back(detail::stage_mesh(mesh, path));
    return files_.back()->bytes();
}

namespace {

// The format's sink into a staged file, put among the outputs once the mesh is whole.
class StagedMeshSink final : public MeshSink {
public:
    StagedMeshSink(const std::string& path, detail::MeshPartsWriter writer,
                   std::vector<std::unique_ptr<AtomicFile>>& files)
        : file_(std::make_unique<AtomicFile>(path)), sink_(writer(*file_)), files_(files) {}
    bool wants_corners() const override { return sink_->wants_corners(); }
    void begin(std::uint64_t vertices, std::uint64_t triangles) override { sink_->begin(vertices, triangles); }
    void vertices(const MeshPart& part) override { sink_->vertices(part); }
    void triangles(const MeshPart& part) override { sink_->triangles(part); }
    void finish() override {
        sink_->finish();
        file_->finish();
        files_.push_back(std::move(file_));
    }

private:
    std::unique_ptr<AtomicFile> file_;
    std::unique_ptr<MeshSink> sink_;
    std::vector<std::unique_ptr<AtomicFile>>& files_;
};

}  // namespace

std::shared_ptr<MeshSink> OutputFiles::mesh_sink(const std::string& path) {
    const detail::MeshPartsWriter writer = detail::format_for(path, FormatUse::WriteMesh).write.parts;
    return writer ? std::make_shared<StagedMeshSink>(path, writer, files_) : nullptr;
}

std::uint64_t OutputFiles::staged_bytes(const std::string& path) const {
    for (const auto& file : files_)
        if (file->target() == path) return file->bytes();
    return 0;
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
