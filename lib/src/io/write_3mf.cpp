// 3MF, the format slicers prefer: one mesh object and its build item, in millimetres,
// made by lib3mf (Debian's lib3mf-dev, the 1.x API) into memory and streamed through
// the AtomicFile like every other output.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Model/COM/NMR_DLLInterfaces.h>

#include "io/atomic_file.hpp"
#include "io/writers.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

struct Release {
    void operator()(NMR::PLib3MFBase* p) const { NMR::lib3mf_release(p); }
};
using Handle = std::unique_ptr<NMR::PLib3MFBase, Release>;

// Throws IoError with lib3mf's own message when a call fails.
void check(LIB3MFRESULT result, NMR::PLib3MFBase* instance, const std::string& path, const char* what) {
    if (result == LIB3MF_OK) return;
    DWORD code = 0;
    LPCSTR message = nullptr;
    if (instance) NMR::lib3mf_getlasterror(instance, &code, &message);
    throw IoError("cannot write '" + path + "': lib3mf could not " + what +
                  (message && *message ? std::string(" (") + message + ")" : std::string()));
}

}  // namespace

void write_3mf(const Mesh& mesh, AtomicFile& out) {
    const std::string& path = out.target();
    NMR::PLib3MFModel* raw_model = nullptr;
    check(NMR::lib3mf_createmodel(&raw_model), nullptr, path, "create a model");
    const Handle model(raw_model);
    check(NMR::lib3mf_model_setunit(raw_model, NMR::MODELUNIT_MILLIMETER), raw_model, path, "set the unit");

    std::vector<NMR::MODELMESHVERTEX> vertices(mesh.vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i)
        for (int a = 0; a < 3; ++a) vertices[i].m_fPosition[a] = float(mesh.vertices[i][std::size_t(a)]);
    std::vector<NMR::MODELMESHTRIANGLE> triangles(mesh.triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) triangles[t].m_nIndices[c] = mesh.triangles[t][std::size_t(c)];

    NMR::PLib3MFModelMeshObject* raw_object = nullptr;
    check(NMR::lib3mf_model_addmeshobject(raw_model, &raw_object), raw_model, path, "add the mesh");
    const Handle object(raw_object);
    check(NMR::lib3mf_meshobject_setgeometry(raw_object, vertices.data(), DWORD(vertices.size()),
                                             triangles.data(), DWORD(triangles.size())),
          raw_object, path, "store the mesh");
    NMR::PLib3MFModelBuildItem* raw_item = nullptr;
    check(NMR::lib3mf_model_addbuilditem(raw_model, raw_object, nullptr, &raw_item), raw_model, path,
          "add the build item");
    const Handle item(raw_item);

    NMR::PLib3MFModelWriter* raw_writer = nullptr;
    check(NMR::lib3mf_model_querywriter(raw_model, "3mf", &raw_writer), raw_model, path, "make a writer");
    const Handle writer(raw_writer);
    ULONG64 size = 0;
    check(NMR::lib3mf_writer_getstreamsize(raw_writer, &size), raw_writer, path, "size the file");
    std::vector<BYTE> bytes(size);
    check(NMR::lib3mf_writer_writetobuffer(raw_writer, bytes.data(), size), raw_writer, path, "write the file");
    out.write(bytes.data(), bytes.size());
}

}  // namespace snvr::detail
