// heldout_ruler: how far a triangle mesh is from the depth frames held out of
// the reconstruction that made it, by levelfuse's ruler (measureHeldOutFrames),
// whoever made the mesh: the whole-process comparison of depth video
// (depth_video_processes.py) measures levelfuse's and Open3D's meshes with it.
//
//   heldout_ruler MESH.ply FOLDER [EVERY OFFSET PIXEL_STRIDE]
//
// FOLDER is depth video as ../shared/data/7scenes-seq holds it; the frames at
// positions OFFSET, OFFSET + EVERY, ... are held out (default 10 and 5: those a
// run with --frame-stride 10 never sees), every PIXEL_STRIDE-th pixel of them in
// each direction (default 2). Prints one JSON object, distances in millimetres.
// Exits 2 with a message naming the file for a mesh or frame it cannot read.

#include "DepthSequence.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/recon/HeldOutFrames.h>

#include <openvdb/openvdb.h>

#include <cstdio>
#include <exception>
#include <string>

namespace levelfuse::bench {
namespace {

/// The triangles of a PLY mesh: vertices x, y, z and faces' vertex_indices,
/// polygons fanned into triangles.
TriangleMesh readPlyMesh(const std::string& path) {
  const io::PlyData ply = io::readPly(path);
  const io::PlyElement* vertices = ply.element("vertex");
  const io::PlyElement* faces = ply.element("face");
  if (!vertices || !faces) throw io::InputError(path, "a mesh has vertex and face elements");
  const int x = vertices->property("x"), y = vertices->property("y"), z = vertices->property("z");
  const int list = faces->property("vertex_indices");
  if (x < 0 || y < 0 || z < 0 || list < 0) throw io::InputError(path, "no x, y, z or vertex_indices");
  TriangleMesh mesh;
  for (std::size_t v = 0; v < vertices->count; ++v)
    for (const int axis : {x, y, z}) mesh.xyz.push_back(static_cast<float>(vertices->values[axis][v]));
  const std::vector<double>& items = faces->values[list];
  const std::vector<std::size_t>& offsets = faces->listOffsets[list];
  for (std::size_t f = 0; f < faces->count; ++f)
    for (std::size_t k = offsets[f] + 2; k < offsets[f + 1]; ++k)
      for (const std::size_t corner : {offsets[f], k - 1, k}) {
        if (items[corner] < 0 || items[corner] >= static_cast<double>(vertices->count))
          throw io::InputError(path, "face " + std::to_string(f) + " names a vertex the mesh does not have");
        mesh.triangles.push_back(static_cast<std::uint32_t>(items[corner]));
      }
  return mesh;
}

void printAccuracy(const HeldOutAccuracy& accuracy) {
  const DataFit& d = accuracy.distances;
  std::printf("{\"points\": %zu, \"mean_mm\": %.4f, \"median_mm\": %.4f, \"p90_mm\": %.4f, "
              "\"within_1cm\": %.5f, \"within_2cm\": %.5f, \"within_5cm\": %.5f}\n",
              d.readings, 1000.0 * d.mean, 1000.0 * d.median, 1000.0 * d.p90, accuracy.within[0],
              accuracy.within[1], accuracy.within[2]);
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) {
  using namespace levelfuse;
  if (argc != 3 && argc != 6) {
    std::fprintf(stderr, "usage: %s MESH.ply FOLDER [EVERY OFFSET PIXEL_STRIDE]\n", argv[0]);
    return 2;
  }
  try {
    openvdb::initialize();
    const int every = argc == 6 ? std::stoi(argv[3]) : 10, offset = argc == 6 ? std::stoi(argv[4]) : 5;
    HeldOutOptions options;
    options.stride = argc == 6 ? std::stoi(argv[5]) : 2;
    const TriangleMesh mesh = bench::readPlyMesh(argv[1]);
    bench::printAccuracy(measureHeldOutFrames(mesh, bench::heldOutFrames(argv[2], every, offset), options));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "heldout_ruler: %s\n", error.what());
    return 2;
  }
  return 0;
}
