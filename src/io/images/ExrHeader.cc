// levelfuse: what an EXR file's header declares.

#include "ExrHeader.h"
#include "../ByteOrder.h"

#include <levelfuse/io/InputError.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <vector>

namespace levelfuse::io::detail {

namespace {

constexpr std::uint32_t kExrMagic = 20000630;
constexpr std::uint32_t kLongNamesFlag = 0x400;
/// Attribute values a header needs to hold are small; a longer one is skipped, not read.
constexpr std::uint32_t kLargestReadValue = 1 << 16;

/// A NUL-terminated string of at most `longest` bytes; false at the end of the file or if longer.
bool readName(std::ifstream& in, std::size_t longest, std::string& name) {
  name.clear();
  for (char c; in.get(c);) {
    if (c == '\0') return true;
    if (name.size() == longest) return false;
    name += c;
  }
  return false;
}

/// Bytes per sample of an EXR pixel type (UINT, HALF, FLOAT); 0 for others.
double sampleBytes(std::uint32_t type) { return type == 1 ? 2.0 : type == 0 || type == 2 ? 4.0 : 0.0; }

}  // namespace

std::string readExrLayout(const std::string& path, std::uintmax_t fileBytes, ExrLayout& layout) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot be opened for reading";
  unsigned char start[8];
  if (!in.read(reinterpret_cast<char*>(start), 8) || littleEndian32(start) != kExrMagic)
    return "not an EXR file (the magic number is missing)";
  const std::size_t longest = littleEndian32(start + 4) & kLongNamesFlag ? 255 : 31;
  bool window = false;
  for (std::string name, type;;) {
    if (!readName(in, longest, name)) return "a truncated or malformed EXR header (an attribute's name)";
    if (name.empty()) break;  // the end of the header
    unsigned char size[4];
    if (!readName(in, longest, type) || !in.read(reinterpret_cast<char*>(size), 4))
      return "a truncated or malformed EXR header (attribute " + quote(name) + ")";
    const std::uint32_t bytes = littleEndian32(size);
    const std::streamoff at = in.tellg();
    if (at < 0 || static_cast<std::uintmax_t>(at) + bytes > fileBytes)
      return "the EXR header's attribute " + quote(name) + " declares " + std::to_string(bytes) +
             " bytes, more than the file holds (truncated?)";
    const bool needed = name == "dataWindow" || name == "compression" || name == "channels";
    if (!needed || bytes > kLargestReadValue) {
      in.seekg(bytes, std::ios::cur);
      continue;
    }
    std::vector<unsigned char> value(bytes);
    if (!in.read(reinterpret_cast<char*>(value.data()), bytes)) return "a truncated EXR header";
    if (name == "dataWindow" && type == "box2i" && bytes == 16) {
      const auto corner = [&](int i) {
        return static_cast<double>(static_cast<std::int32_t>(littleEndian32(&value[4 * static_cast<std::size_t>(i)])));
      };
      layout.width = corner(2) - corner(0) + 1.0;
      layout.height = corner(3) - corner(1) + 1.0;
      window = true;
    } else if (name == "compression" && bytes == 1) {
      layout.compression = value[0];
    } else if (name == "channels") {
      // name\0, pixel type, pLinear and 3 reserved bytes, x and y sampling; a NUL ends the list.
      layout.bytesPerPixel = 0.0;
      std::size_t i = 0;
      while (i < value.size() && value[i] != 0) {
        const auto end = std::find(value.begin() + static_cast<std::ptrdiff_t>(i), value.end(), 0);
        i = static_cast<std::size_t>(end - value.begin()) + 1;
        if (i + 16 > value.size()) return "a malformed EXR channel list";
        const double xSampling = std::max<std::uint32_t>(1, littleEndian32(&value[i + 8]));
        const double ySampling = std::max<std::uint32_t>(1, littleEndian32(&value[i + 12]));
        layout.bytesPerPixel += sampleBytes(littleEndian32(&value[i])) / (xSampling * ySampling);
        i += 16;
      }
    }
  }
  if (!window) return "the EXR header has no data window";
  return "";
}

double exrMaxCompressionRatio(int compression) {
  switch (compression) {
    case 0: return 1.0;                  // none
    case 1: return 64.0;                 // RLE: runs of at most 128 bytes in 2
    case 2: case 3: return 1032.0;       // ZIP: deflate's largest ratio
    case 5: return 1032.0 * 4.0 / 3.0;   // PXR24: floats to 24 bits, then deflate
    default: return 4096.0;              // PIZ, B44, DWA and schemes to come
  }
}

}  // namespace levelfuse::io::detail
