// levelfuse: a small, strict PLY reader and writer.
//
// Reads ASCII and binary (both endiannesses) PLY files into columns of
// numbers. Strict: every count, type and value is checked, and the sizes the
// header declares are checked against the file before anything is allocated.
// Header lines that are not PLY keywords (real scanner files have them) are
// skipped with a warning.
#pragma once

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/core/MemoryBudget.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse::io {

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
enum class PlyType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;  ///< the value type (items of a list)
  bool isList = false;
  PlyType countType = PlyType::kUInt8;  ///< lists only
};

/// One element: scalar properties as columns, list properties as offsets into a
/// flat array of items.
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  /// Per property: the column of values (scalars), or the list items (lists).
  std::vector<std::vector<double>> values;
  /// Per property: for lists, count + 1 offsets into values[p]; empty for scalars.
  std::vector<std::vector<std::size_t>> listOffsets;

  /// Index of a property by name, or -1.
  int property(const std::string& name) const;
};

struct PlyData {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<std::string> comments;
  std::vector<std::pair<std::string, std::string>> objInfo;  ///< `obj_info key value` lines
  std::vector<PlyElement> elements;
  std::vector<std::string> warnings;  ///< what was tolerated, e.g. unknown header lines

  const PlyElement* element(const std::string& name) const;
  /// The value of an `obj_info key value` line, or "" if there is none.
  std::string info(const std::string& key) const;
};

/// Reads a PLY file; throws InputError naming the file and the problem, also
/// for a file that would need more memory than `budget` allows.
PlyData readPly(const std::string& path, const MemoryBudget& budget = {});

/// Writes a triangle mesh (float vertices, int triangles) as binary
/// PLY in the machine's byte order, little-endian on x86-64 and arm64 (or
/// ASCII), atomically: temporary file, then rename.
/// `rgb`, if not empty, is three bytes per vertex, written as the vertices'
/// uchar red, green and blue.
void writeMeshPly(const std::string& path, const std::vector<float>& xyz, const std::vector<std::uint32_t>& triangles,
                  bool binary = true, const std::vector<std::uint8_t>& rgb = {});
/// The same, as one of a run's outputs: committed with the others (AtomicWrite.h).
void writeMeshPly(OutputSet& outputs, const std::string& path, const std::vector<float>& xyz,
                  const std::vector<std::uint32_t>& triangles, bool binary = true,
                  const std::vector<std::uint8_t>& rgb = {});

}  // namespace levelfuse::io
