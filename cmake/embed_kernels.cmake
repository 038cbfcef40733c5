# Writes OUTPUT, a C++ file holding the OpenCL C sources of KERNEL_DIR (common.cl first,
# then every other .cl file by name), so the library needs no .cl file at run time.
file(GLOB sources "${KERNEL_DIR}/*.cl")
list(SORT sources)
list(REMOVE_ITEM sources "${KERNEL_DIR}/common.cl")
list(PREPEND sources "${KERNEL_DIR}/common.cl")
set(body "")
foreach(src ${sources})
  get_filename_component(name ${src} NAME)
  file(READ ${src} text)
  # #line: compiler messages name the kernel file and its line.
  string(APPEND body "    {\"${name}\", R\"snvr_cl(#line 1 \"${name}\"\n${text})snvr_cl\"},\n")
endforeach()
file(WRITE "${OUTPUT}.tmp"
"// Generated from kernels/*.cl by cmake/embed_kernels.cmake: do not edit.
#include \"opencl/kernel_sources.hpp\"

namespace snvr {

const std::vector<KernelSource>& kernel_sources() {
    static const std::vector<KernelSource> sources = {
${body}    };
    return sources;
}

}  // namespace snvr
")
# Only touch the output when it changed, so unrelated builds do not recompile it.
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
