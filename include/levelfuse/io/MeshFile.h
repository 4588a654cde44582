// levelfuse: triangle meshes as files.
#pragma once

#include <levelfuse/levelset/Mesh.h>

#include <string>

namespace levelfuse::io {

/// Writes `mesh` by the file's extension: `.ply` (binary little-endian) or
/// `.obj` (text), atomically. Throws std::invalid_argument for another
/// extension, std::runtime_error naming `path` if it cannot be written.
void writeMesh(const std::string& path, const TriangleMesh& mesh);

}  // namespace levelfuse::io
