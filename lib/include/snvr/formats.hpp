// The file formats libsnvr reads and writes, as their extensions (lib/src/io/formats.cpp
// holds the table: one row a format).
#pragma once
#include <string>

namespace snvr {

// What is done with a file format, for format_extensions.
enum class FormatUse { ReadPoints, ReadMesh, WriteMesh, WritePoints, WriteField };

// The extensions the readers or writers take for `use`, for help texts: ".stl, .ply,
// .obj or .3mf" for WriteMesh. The readers also take each of theirs gzipped (".gz" added).
std::string format_extensions(FormatUse use);
// Whether path's extension names a format that serves `use` (".gz" after it for reading).
bool format_serves(const std::string& path, FormatUse use);

}  // namespace snvr
