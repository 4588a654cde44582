// levelfuse: mesh files.

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/io/outputs/MeshFile.h>

#include "../FileExtension.h"

#include <cstdio>
#include <stdexcept>

namespace levelfuse::io {

namespace {

void writeObj(OutputSet& outputs, const std::string& path, const TriangleMesh& mesh) {
  outputs.add(path, [&](const std::string& temporary) {
    std::FILE* file = std::fopen(temporary.c_str(), "w");
    if (!file) throw std::runtime_error("cannot open a temporary file beside it");
    std::fprintf(file, "# written by levelfuse: %zu vertices, %zu triangles\n", mesh.vertexCount(),
                 mesh.triangleCount());
    // Vertex colours as OBJ readers take them (MeshLab, Blender): r g b from 0 to 1 after the position.
    for (std::size_t i = 0; i < mesh.xyz.size(); i += 3)
      if (mesh.hasColours())
        std::fprintf(file, "v %.9g %.9g %.9g %.6g %.6g %.6g\n", mesh.xyz[i], mesh.xyz[i + 1], mesh.xyz[i + 2],
                     mesh.rgb[i] / 255.0, mesh.rgb[i + 1] / 255.0, mesh.rgb[i + 2] / 255.0);
      else
        std::fprintf(file, "v %.9g %.9g %.9g\n", mesh.xyz[i], mesh.xyz[i + 1], mesh.xyz[i + 2]);
    for (std::size_t t = 0; t < mesh.triangles.size(); t += 3)  // OBJ counts vertices from 1
      std::fprintf(file, "f %u %u %u\n", mesh.triangles[t] + 1, mesh.triangles[t + 1] + 1, mesh.triangles[t + 2] + 1);
    const bool failed = std::fflush(file) != 0 || std::ferror(file) != 0;
    if (std::fclose(file) != 0 || failed) throw std::runtime_error("write error (disk full?)");
  });
}

}  // namespace

void requireMeshFileName(const std::string& path) {
  const std::string extension = detail::lowercaseExtension(path);
  if (extension != ".ply" && extension != ".obj")
    throw std::invalid_argument("cannot write a mesh as '" + path + "': the name must end in .ply or .obj");
}

void writeMesh(OutputSet& outputs, const std::string& path, const TriangleMesh& mesh) {
  requireMeshFileName(path);
  if (detail::lowercaseExtension(path) == ".ply") return writeMeshPly(outputs, path, mesh.xyz, mesh.triangles, true, mesh.rgb);
  writeObj(outputs, path, mesh);
}

void writeMesh(const std::string& path, const TriangleMesh& mesh) {
  OutputSet outputs;
  writeMesh(outputs, path, mesh);
  outputs.commit();
}

}  // namespace levelfuse::io
