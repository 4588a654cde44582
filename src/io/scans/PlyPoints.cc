// levelfuse: the vertices of a PLY file as points (readPlyPoints; the format
// is described in PointScans.h).

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/io/scans/PointScans.h>

#include <cmath>
#include <cstdint>
#include <string>

namespace levelfuse::io {

namespace {

const char* const kColourNames[3] = {"red", "green", "blue"};

/// The index of the vertex's scalar property `name`, or -1 if it has none.
int scalarProperty(const PlyElement& vertex, const std::string& name, const std::string& path) {
  const int p = vertex.property(name);
  if (p >= 0 && vertex.properties[static_cast<std::size_t>(p)].isList)
    throw InputError(path, "the vertex property '" + name + "' is a list, not a number");
  return p;
}

bool isFloat(PlyType type) { return type == PlyType::kFloat32 || type == PlyType::kFloat64; }

/// A colour channel as written: uchar 0 to 255 as it is, float 0 to 1 scaled
/// to 0 to 255.
std::uint8_t channelOf(double value, bool scaled, std::size_t vertex, const char* name, const std::string& path) {
  if (scaled && !(value >= 0.0 && value <= 1.0))
    throw InputError(path, "vertex " + std::to_string(vertex) + ": " + name + " " + std::to_string(value) +
                               " is outside 0 to 1 (a float colour)");
  return static_cast<std::uint8_t>(scaled ? std::lround(value * 255.0) : std::lround(value));
}

std::vector<Rgb8> coloursOf(const PlyElement& vertex, const std::string& path) {
  int channels[3];
  int present = 0;
  for (int c = 0; c < 3; ++c) present += (channels[c] = scalarProperty(vertex, kColourNames[c], path)) >= 0;
  if (present == 0) return {};
  if (present < 3) throw InputError(path, "the vertices have some of 'red', 'green' and 'blue' but not all three");
  const PlyType type = vertex.properties[static_cast<std::size_t>(channels[0])].type;
  for (const int c : channels) {
    const PlyType t = vertex.properties[static_cast<std::size_t>(c)].type;
    if (t != type || (t != PlyType::kUInt8 && !isFloat(t)))
      throw InputError(path, "the vertex colours must all be uchar (0 to 255) or all float or double (0 to 1)");
  }
  std::vector<Rgb8> colours(vertex.count);
  for (std::size_t i = 0; i < vertex.count; ++i)
    for (int c = 0; c < 3; ++c)
      colours[i][static_cast<std::size_t>(c)] =
          channelOf(vertex.values[static_cast<std::size_t>(channels[c])][i], isFloat(type), i, kColourNames[c], path);
  return colours;
}

}  // namespace

PointCloud readPlyPoints(const std::string& path, const MemoryBudget& budget) {
  const PlyData ply = readPly(path, budget);
  const PlyElement* vertex = ply.element("vertex");
  if (!vertex) throw InputError(path, "no 'vertex' element: no points");
  const int px = scalarProperty(*vertex, "x", path), py = scalarProperty(*vertex, "y", path),
            pz = scalarProperty(*vertex, "z", path);
  if (px < 0 || py < 0 || pz < 0) throw InputError(path, "the vertices have no x, y and z");
  if (vertex->count == 0) throw InputError(path, "no points: the 'vertex' element is empty");
  PointCloud cloud;
  cloud.points.reserve(vertex->count);
  for (std::size_t i = 0; i < vertex->count; ++i) {
    const openvdb::Vec3d p(vertex->values[static_cast<std::size_t>(px)][i],
                           vertex->values[static_cast<std::size_t>(py)][i],
                           vertex->values[static_cast<std::size_t>(pz)][i]);
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw InputError(path, "vertex " + std::to_string(i) + " has a coordinate that is not finite");
    cloud.points.push_back(p);
  }
  cloud.colours = coloursOf(*vertex, path);
  return cloud;
}

}  // namespace levelfuse::io
