# Writes OUTPUT, a C++ file holding the OpenCL C sources of KERNEL_DIR (common.cl first,
# then every other .cl file by name), so the library needs no .cl file at run time. A
# line `#include "x.h"` in a .cl file is replaced by KERNEL_DIR/x.h (phase_math.h, which
# the C++ side includes too): the program has no file to find at run time either.
file(GLOB sources "${KERNEL_DIR}/*.cl")
list(SORT sources)
list(REMOVE_ITEM sources "${KERNEL_DIR}/common.cl")
list(PREPEND sources "${KERNEL_DIR}/common.cl")
set(body "")
foreach(src ${sources})
  get_filename_component(name ${src} NAME)
  file(READ ${src} text)
  string(REGEX MATCHALL "#include \"[^\"]+\"" includes "${text}")
  foreach(directive ${includes})
    string(REGEX REPLACE "#include \"([^\"]+)\"" "\\1" header "${directive}")
    if(NOT EXISTS "${KERNEL_DIR}/${header}")
      message(FATAL_ERROR "${name}: ${directive}: no ${KERNEL_DIR}/${header}")
    endif()
    file(READ "${KERNEL_DIR}/${header}" header_text)
    # The directive's line number, for the #line that resumes the .cl file after it.
    string(FIND "${text}" "${directive}" at)
    string(SUBSTRING "${text}" 0 ${at} before)
    string(REGEX MATCHALL "\n" newlines "${before}")
    list(LENGTH newlines line)
    math(EXPR next "${line} + 2")
    string(REPLACE "${directive}" "#line 1 \"${header}\"\n${header_text}#line ${next} \"${name}\"" text "${text}")
  endforeach()
  # #line: compiler messages name the kernel file and its line.
  string(APPEND body "    {\"${name}\", R\"snvr_cl(#line 1 \"${name}\"\n${text})snvr_cl\"},\n")
endforeach()
file(WRITE "${OUTPUT}.tmp"
"// Generated from kernels/*.cl and the headers they include by cmake/embed_kernels.cmake: do not edit.
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
