// levelfuse: triangle meshes as files.
#pragma once

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/levelset/Mesh.h>

#include <string>

namespace levelfuse::io {

/// Writes `mesh` by the file's extension: `.ply` (binary, the machine's byte order) or
/// `.obj` (text), atomically. Throws std::invalid_argument for another
/// extension, std::runtime_error naming `path` if it cannot be written.
void writeMesh(const std::string& path, const TriangleMesh& mesh);
/// The same, as one of a run's outputs: committed with the others (AtomicWrite.h).
void writeMesh(OutputSet& outputs, const std::string& path, const TriangleMesh& mesh);

/// Throws std::invalid_argument unless `path` names a mesh file writeMesh
/// writes (.ply or .obj, in either case).
void requireMeshFileName(const std::string& path);

}  // namespace levelfuse::io
