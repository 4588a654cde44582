// Point files for tests.

#include "support/PointFiles.h"

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace levelfuse::test {

namespace {

std::string number(double x) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.9g", x);
  return text;
}

template <typename T>
void appendLittleEndian(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the tests run on little-endian machines
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

/// The column-vector matrix of a row-vector pose, its top `rows` rows, row by row.
std::string columnVectorRows(const openvdb::math::Mat4d& pose, int rows, const std::string& separator) {
  std::string text;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < 4; ++c) text += (text.empty() ? "" : separator) + number(pose(c, r));
  return text;
}

}  // namespace

std::string xyzText(const std::vector<openvdb::Vec3d>& points, const std::vector<Rgb8>& colours) {
  std::string text;
  for (std::size_t i = 0; i < points.size(); ++i) {
    text += number(points[i].x()) + " " + number(points[i].y()) + " " + number(points[i].z());
    if (!colours.empty())
      for (const std::uint8_t c : colours[i]) text += " " + std::to_string(c);
    text += "\n";
  }
  return text;
}

std::string plyPoints(const std::vector<openvdb::Vec3d>& points, const std::vector<Rgb8>& colours, bool binary) {
  std::string text = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                     " 1.0\nelement vertex " + std::to_string(points.size()) +
                     "\nproperty double x\nproperty double y\nproperty double z\n";
  if (!colours.empty()) text += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  text += "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
  if (!binary) return text + xyzText(points, colours);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) appendLittleEndian(text, points[i][k]);
    if (!colours.empty())
      for (const std::uint8_t c : colours[i]) appendLittleEndian(text, c);
  }
  return text;
}

std::vector<unsigned char> kittiBinBytes(const std::vector<openvdb::Vec3d>& points) {
  std::string bytes;
  for (const openvdb::Vec3d& p : points) {
    for (int k = 0; k < 3; ++k) appendLittleEndian(bytes, static_cast<float>(p[k]));
    appendLittleEndian(bytes, 0.5f);
  }
  return std::vector<unsigned char>(bytes.begin(), bytes.end());
}

std::string kittiTransformText(const openvdb::math::Mat4d& rowVectorPose) {
  return columnVectorRows(rowVectorPose, 3, " ");
}

std::string manifestPose(const openvdb::math::Mat4d& rowVectorPose) {
  return "[" + columnVectorRows(rowVectorPose, 4, ", ") + "]";
}

std::vector<Rgb8> someColours(std::size_t count) {
  std::vector<Rgb8> colours;
  for (std::size_t i = 0; i < count; ++i)
    colours.push_back(Rgb8{static_cast<std::uint8_t>(i * 7 % 256), static_cast<std::uint8_t>(i * 13 % 256), 255});
  return colours;
}

}  // namespace levelfuse::test
