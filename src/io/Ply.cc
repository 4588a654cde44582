// levelfuse: a small, strict PLY reader and writer.

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/MemoryBudget.h>
#include <levelfuse/io/Ply.h>

#include "ByteOrder.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>

namespace levelfuse::io {

namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 20;
const char* const kScanTooLargeAdvice = "split the scan into smaller files, or use a machine with more memory";

std::size_t sizeOf(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUInt8: return 1;
    case PlyType::kInt16:
    case PlyType::kUInt16: return 2;
    case PlyType::kInt32:
    case PlyType::kUInt32:
    case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 0;
}

bool isInteger(PlyType t) { return t != PlyType::kFloat32 && t != PlyType::kFloat64; }

bool parseType(const std::string& name, PlyType& t) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::kInt8},     {"int8", PlyType::kInt8},       {"uchar", PlyType::kUInt8},
      {"uint8", PlyType::kUInt8},   {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUInt16}, {"uint16", PlyType::kUInt16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},   {"uint", PlyType::kUInt32},     {"uint32", PlyType::kUInt32},
      {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [n, type] : kNames)
    if (name == n) {
      t = type;
      return true;
    }
  return false;
}

/// Range of an integer type.
void limits(PlyType t, double& lo, double& hi) {
  switch (t) {
    case PlyType::kInt8: lo = -128; hi = 127; break;
    case PlyType::kUInt8: lo = 0; hi = 255; break;
    case PlyType::kInt16: lo = -32768; hi = 32767; break;
    case PlyType::kUInt16: lo = 0; hi = 65535; break;
    case PlyType::kInt32: lo = -2147483648.0; hi = 2147483647.0; break;
    case PlyType::kUInt32: lo = 0; hi = 4294967295.0; break;
    default: lo = -std::numeric_limits<double>::max(); hi = std::numeric_limits<double>::max(); break;
  }
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> words;
  std::istringstream in(line);
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

std::string readWholeFile(const std::string& path, const MemoryBudget& budget) {
  requireInputFile(path);
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec) requireMemory(budget, path, static_cast<double>(size), "reading the file", kScanTooLargeAdvice);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot be opened for reading");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path, "read error");
  return bytes;
}

class Parser {
 public:
  Parser(std::string path, std::string bytes, const MemoryBudget& budget)
      : mPath(std::move(path)), mBytes(std::move(bytes)), mBudget(budget) {}

  PlyData parse() {
    parseHeader();
    checkSizes();
    for (PlyElement& e : mData.elements) {
      if (mData.format == PlyFormat::kAscii) readAscii(e);
      else readBinary(e);
    }
    finish();
    return std::move(mData);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const { throw InputError(mPath, problem); }

  void parseHeader() {
    std::size_t lineNo = 0;
    bool sawFormat = false;
    while (true) {
      if (mPos >= mBytes.size() || mPos > kMaxHeaderBytes)
        fail(mPos >= mBytes.size() ? "the header has no end_header line (empty or truncated file?)"
                                   : "no end_header within the first 1 MiB: not a PLY file");
      const std::size_t eol = mBytes.find('\n', mPos);
      if (eol == std::string::npos) fail("the header has no end_header line (truncated file?)");
      std::string line = mBytes.substr(mPos, eol - mPos);
      mPos = eol + 1;
      ++lineNo;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const std::vector<std::string> w = split(line);
      if (lineNo == 1) {
        if (w.size() != 1 || w[0] != "ply") fail("not a PLY file (the first line is not 'ply')");
        continue;
      }
      if (w.empty()) continue;
      const std::string& key = w[0];
      const std::string at = "header line " + std::to_string(lineNo) + ": ";
      if (key == "end_header") break;
      if (key == "format") {
        if (w.size() != 3) fail(at + "expected 'format <type> 1.0'");
        if (w[1] == "ascii") mData.format = PlyFormat::kAscii;
        else if (w[1] == "binary_little_endian") mData.format = PlyFormat::kBinaryLittleEndian;
        else if (w[1] == "binary_big_endian") mData.format = PlyFormat::kBinaryBigEndian;
        else fail(at + "unknown format " + quote(w[1]));
        if (w[2] != "1.0") mData.warnings.push_back(at + "format version " + w[2] + " read as 1.0");
        sawFormat = true;
      } else if (key == "comment") {
        mData.comments.push_back(line.size() > 8 ? line.substr(8) : "");
      } else if (key == "obj_info") {
        mData.objInfo.emplace_back(w.size() > 1 ? w[1] : "", w.size() > 2 ? w[2] : "");
      } else if (key == "element") {
        if (w.size() != 3) fail(at + "expected 'element <name> <count>'");
        PlyElement e;
        e.name = w[1];
        const char* b = w[2].data();
        const auto [end, ec] = std::from_chars(b, b + w[2].size(), e.count);
        if (ec != std::errc() || end != b + w[2].size())
          fail(at + "element " + quote(w[1]) + " has an invalid count " + quote(w[2]));
        mData.elements.push_back(std::move(e));
      } else if (key == "property") {
        if (mData.elements.empty()) fail(at + "a property before any element");
        PlyProperty p;
        if (w.size() == 5 && w[1] == "list") {
          p.isList = true;
          if (!parseType(w[2], p.countType) || !isInteger(p.countType))
            fail(at + "invalid list count type " + quote(w[2]));
          if (!parseType(w[3], p.type)) fail(at + "unknown type " + quote(w[3]));
          p.name = w[4];
        } else if (w.size() == 3) {
          if (!parseType(w[1], p.type)) fail(at + "unknown type " + quote(w[1]));
          p.name = w[2];
        } else {
          fail(at + "expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
        }
        mData.elements.back().properties.push_back(p);
      } else {
        mData.warnings.push_back(at + "skipped unknown header line " + quote(line));
      }
    }
    if (!sawFormat) fail("the header has no format line");
    mLine = lineNo + 1;
  }

  /// Rejects counts the rest of the file cannot hold, and values that would
  /// not fit in memory, before allocating anything.
  void checkSizes() {
    const double remaining = static_cast<double>(mBytes.size() - mPos);
    double needed = 0.0, valueBytes = 0.0;
    for (const PlyElement& e : mData.elements) {
      if (e.count > 0 && e.properties.empty())
        fail("element " + quote(e.name) + " declares " + std::to_string(e.count) + " entries but no properties");
      double perEntry = 0.0;
      for (const PlyProperty& p : e.properties) {
        if (mData.format == PlyFormat::kAscii) perEntry += 2.0;  // a digit and a separator at least
        else perEntry += static_cast<double>(p.isList ? sizeOf(p.countType) : sizeOf(p.type));
      }
      needed += perEntry * static_cast<double>(e.count);
      if (needed > remaining)
        fail("element " + quote(e.name) + " declares " + std::to_string(e.count) + " entries, but only " +
             std::to_string(mBytes.size() - mPos) + " bytes follow the header (truncated file or a wrong count?)");
      // A double per scalar; per list, offsets and at most as many items as the bytes left can hold.
      for (const PlyProperty& p : e.properties) {
        const double itemBytes = mData.format == PlyFormat::kAscii ? 2.0 : static_cast<double>(sizeOf(p.type));
        valueBytes += p.isList ? sizeof(std::size_t) * (static_cast<double>(e.count) + 1.0) +
                                     sizeof(double) * remaining / itemBytes
                               : sizeof(double) * static_cast<double>(e.count);
      }
    }
    requireMemory(mBudget, mPath, static_cast<double>(mBytes.size()) + valueBytes, "reading its values", kScanTooLargeAdvice);
    for (PlyElement& e : mData.elements) {
      e.values.resize(e.properties.size());
      e.listOffsets.resize(e.properties.size());
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        if (e.properties[p].isList) e.listOffsets[p].reserve(e.count + 1);
        else e.values[p].reserve(e.count);
      }
    }
  }

  // ---- ASCII ----
  void skipSpaces() {
    while (mPos < mBytes.size() && (mBytes[mPos] == ' ' || mBytes[mPos] == '\t' || mBytes[mPos] == '\r')) ++mPos;
  }

  double asciiNumber(const PlyElement& e, std::size_t entry, PlyType type) {
    skipSpaces();
    if (mPos >= mBytes.size())
      fail("the file ends in " + quote(e.name) + " entry " + std::to_string(entry) + " of " + std::to_string(e.count) +
           " (truncated?)");
    if (mBytes[mPos] == '\n')
      fail("line " + std::to_string(mLine) + ": " + quote(e.name) + " entry " + std::to_string(entry) +
           " has fewer values than its " + std::to_string(e.properties.size()) + " properties");
    const char* b = mBytes.data() + mPos;
    const char* end = mBytes.data() + mBytes.size();
    double v = 0.0;
    const auto [next, ec] = std::from_chars(b, end, v);
    if (ec != std::errc() || (next < end && *next != ' ' && *next != '\t' && *next != '\n' && *next != '\r')) {
      const char* stop = b;
      while (stop < end && *stop != ' ' && *stop != '\n' && stop - b < 32) ++stop;
      fail("line " + std::to_string(mLine) + ": " + quote(std::string(b, stop)) + " is not a number");
    }
    mPos = static_cast<std::size_t>(next - mBytes.data());
    if (isInteger(type)) {
      double lo, hi;
      limits(type, lo, hi);
      if (v != std::floor(v) || v < lo || v > hi)
        fail("line " + std::to_string(mLine) + ": " + std::to_string(v) + " does not fit the integer type of " +
             quote(e.name));
    }
    return v;
  }

  void readAscii(PlyElement& e) {
    for (std::size_t entry = 0; entry < e.count; ++entry) {
      // Skip blank lines between entries.
      while (true) {
        skipSpaces();
        if (mPos < mBytes.size() && mBytes[mPos] == '\n') {
          ++mPos;
          ++mLine;
          continue;
        }
        break;
      }
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        if (!prop.isList) {
          e.values[p].push_back(asciiNumber(e, entry, prop.type));
          continue;
        }
        const double n = asciiNumber(e, entry, prop.countType);
        if (n < 0) fail("line " + std::to_string(mLine) + ": a negative list length");
        if (e.listOffsets[p].empty()) e.listOffsets[p].push_back(0);
        for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i)
          e.values[p].push_back(asciiNumber(e, entry, prop.type));
        e.listOffsets[p].push_back(e.values[p].size());
      }
      skipSpaces();
      if (mPos < mBytes.size() && mBytes[mPos] != '\n')
        fail("line " + std::to_string(mLine) + ": " + quote(e.name) + " entry " + std::to_string(entry) +
             " has more values than its " + std::to_string(e.properties.size()) + " properties");
      if (mPos < mBytes.size()) {
        ++mPos;
        ++mLine;
      }
    }
  }

  // ---- binary ----
  double binaryNumber(const PlyElement& e, std::size_t entry, PlyType type) {
    const std::size_t n = sizeOf(type);
    if (mPos + n > mBytes.size())
      fail("the file ends in " + quote(e.name) + " entry " + std::to_string(entry) + " of " + std::to_string(e.count) +
           " (truncated?)");
    unsigned char raw[8];
    std::memcpy(raw, mBytes.data() + mPos, n);
    mPos += n;
    detail::toHostOrder(raw, n, mData.format == PlyFormat::kBinaryLittleEndian);
    switch (type) {
      case PlyType::kInt8: { std::int8_t v; std::memcpy(&v, raw, 1); return v; }
      case PlyType::kUInt8: { std::uint8_t v; std::memcpy(&v, raw, 1); return v; }
      case PlyType::kInt16: { std::int16_t v; std::memcpy(&v, raw, 2); return v; }
      case PlyType::kUInt16: { std::uint16_t v; std::memcpy(&v, raw, 2); return v; }
      case PlyType::kInt32: { std::int32_t v; std::memcpy(&v, raw, 4); return v; }
      case PlyType::kUInt32: { std::uint32_t v; std::memcpy(&v, raw, 4); return v; }
      case PlyType::kFloat32: { float v; std::memcpy(&v, raw, 4); return v; }
      case PlyType::kFloat64: { double v; std::memcpy(&v, raw, 8); return v; }
    }
    return 0.0;
  }

  void readBinary(PlyElement& e) {
    for (std::size_t entry = 0; entry < e.count; ++entry)
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        if (!prop.isList) {
          e.values[p].push_back(binaryNumber(e, entry, prop.type));
          continue;
        }
        const double n = binaryNumber(e, entry, prop.countType);
        if (n < 0) fail(quote(e.name) + " entry " + std::to_string(entry) + " has a negative list length");
        if (mPos + static_cast<std::size_t>(n) * sizeOf(prop.type) > mBytes.size())
          fail("the file ends in " + quote(e.name) + " entry " + std::to_string(entry) + " (truncated?)");
        if (e.listOffsets[p].empty()) e.listOffsets[p].push_back(0);
        for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i)
          e.values[p].push_back(binaryNumber(e, entry, prop.type));
        e.listOffsets[p].push_back(e.values[p].size());
      }
  }

  void finish() {
    for (PlyElement& e : mData.elements)
      for (std::size_t p = 0; p < e.properties.size(); ++p)
        if (e.properties[p].isList && e.listOffsets[p].empty()) e.listOffsets[p].push_back(0);
    if (mData.format == PlyFormat::kAscii) {
      const std::size_t rest = mBytes.find_first_not_of(" \t\r\n", mPos);
      if (rest != std::string::npos)
        fail("line " + std::to_string(mLine) + ": data after the last declared element (a count that is too small?)");
    } else if (mPos < mBytes.size()) {
      mData.warnings.push_back(std::to_string(mBytes.size() - mPos) + " bytes after the last element were ignored");
    }
  }

  std::string mPath, mBytes;
  MemoryBudget mBudget;
  std::size_t mPos = 0, mLine = 1;
  PlyData mData;
};

}  // namespace

int PlyElement::property(const std::string& n) const {
  for (std::size_t p = 0; p < properties.size(); ++p)
    if (properties[p].name == n) return static_cast<int>(p);
  return -1;
}

const PlyElement* PlyData::element(const std::string& n) const {
  for (const PlyElement& e : elements)
    if (e.name == n) return &e;
  return nullptr;
}

std::string PlyData::info(const std::string& key) const {
  for (const auto& [k, v] : objInfo)
    if (k == key) return v;
  return "";
}

PlyData readPly(const std::string& path, const MemoryBudget& budget) {
  return Parser(path, readWholeFile(path, budget), budget).parse();
}

void writeMeshPly(const std::string& path, const std::vector<float>& xyz, const std::vector<std::uint32_t>& triangles,
                  bool binary, const std::vector<std::uint8_t>& rgb) {
  OutputSet outputs;
  writeMeshPly(outputs, path, xyz, triangles, binary, rgb);
  outputs.commit();
}

namespace {

/// A mesh's arrays as writeMeshPly takes them.
struct MeshArrays {
  const std::vector<float>& xyz;
  const std::vector<std::uint32_t>& triangles;
  const std::vector<std::uint8_t>& rgb;  ///< three per vertex, or none
};

void writeMeshHeader(std::ostream& out, const MeshArrays& mesh, bool binary) {
  // Binary values are written in the machine's order, which the header states.
  const char* binaryFormat = detail::hostIsLittleEndian() ? "binary_little_endian" : "binary_big_endian";
  out << "ply\nformat " << (binary ? binaryFormat : "ascii") << " 1.0\n"
      << "comment written by levelfuse\n"
      << "element vertex " << mesh.xyz.size() / 3 << "\nproperty float x\nproperty float y\nproperty float z\n"
      << (mesh.rgb.empty() ? "" : "property uchar red\nproperty uchar green\nproperty uchar blue\n")
      << "element face " << mesh.triangles.size() / 3 << "\nproperty list uchar int vertex_indices\nend_header\n";
}

/// Bytes gathered in memory and written to a stream a chunk at a time: a
/// mesh's millions of small records cost one stream write per chunk; a run
/// of bytes as long as a chunk goes to the stream at once, not copied.
class ChunkedWriter {
 public:
  explicit ChunkedWriter(std::ostream& out) : mOut(out) { mChunk.reserve(kChunkBytes); }
  ~ChunkedWriter() { flush(); }
  ChunkedWriter(const ChunkedWriter&) = delete;
  ChunkedWriter& operator=(const ChunkedWriter&) = delete;
  void put(const void* bytes, std::size_t count) {
    if (mChunk.size() + count > kChunkBytes) flush();
    const char* first = static_cast<const char*>(bytes);
    if (count >= kChunkBytes) {
      mOut.write(first, static_cast<std::streamsize>(count));
      return;
    }
    mChunk.insert(mChunk.end(), first, first + count);
  }
  void flush() {
    mOut.write(mChunk.data(), static_cast<std::streamsize>(mChunk.size()));
    mChunk.clear();
  }

 private:
  static constexpr std::size_t kChunkBytes = std::size_t(1) << 20;
  std::ostream& mOut;
  std::vector<char> mChunk;
};

void writeBinaryMesh(std::ostream& out, const MeshArrays& mesh) {
  ChunkedWriter chunks(out);
  if (mesh.rgb.empty()) {
    chunks.put(mesh.xyz.data(), mesh.xyz.size() * sizeof(float));
  } else {
    for (std::size_t i = 0; i < mesh.xyz.size(); i += 3) {
      chunks.put(&mesh.xyz[i], 3 * sizeof(float));
      chunks.put(&mesh.rgb[i], 3);
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const unsigned char three = 3;
    const std::int32_t tri[3] = {static_cast<std::int32_t>(mesh.triangles[t]),
                                 static_cast<std::int32_t>(mesh.triangles[t + 1]),
                                 static_cast<std::int32_t>(mesh.triangles[t + 2])};
    chunks.put(&three, 1);
    chunks.put(tri, sizeof(tri));
  }
}

void writeAsciiMesh(std::ostream& out, const MeshArrays& mesh) {
  out.precision(9);
  for (std::size_t i = 0; i < mesh.xyz.size(); i += 3) {
    out << mesh.xyz[i] << ' ' << mesh.xyz[i + 1] << ' ' << mesh.xyz[i + 2];
    if (!mesh.rgb.empty()) out << ' ' << +mesh.rgb[i] << ' ' << +mesh.rgb[i + 1] << ' ' << +mesh.rgb[i + 2];
    out << '\n';
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3)
    out << "3 " << mesh.triangles[t] << ' ' << mesh.triangles[t + 1] << ' ' << mesh.triangles[t + 2] << '\n';
}

}  // namespace

void writeMeshPly(OutputSet& outputs, const std::string& path, const std::vector<float>& xyz,
                  const std::vector<std::uint32_t>& triangles, bool binary, const std::vector<std::uint8_t>& rgb) {
  if (xyz.size() % 3 != 0 || triangles.size() % 3 != 0)
    throw std::invalid_argument("writeMeshPly: coordinates and triangle indices come in threes");
  if (!rgb.empty() && rgb.size() != xyz.size())
    throw std::invalid_argument("writeMeshPly: a coloured mesh needs one colour per vertex");
  const MeshArrays mesh{xyz, triangles, rgb};
  outputs.add(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) throw std::runtime_error("cannot open a temporary file beside it");
    writeMeshHeader(out, mesh, binary);
    if (binary)
      writeBinaryMesh(out, mesh);
    else
      writeAsciiMesh(out, mesh);
    closeChecked(out);
  });
}

}  // namespace levelfuse::io
