// levelfuse: the physical layer of an ASTM E57 file (private to the E57
// reader): its 48-byte header, and its logical bytes read from 1024-byte
// pages whose last 4 bytes are a CRC-32C of the other 1020, stored
// big-endian. Every page a read touches has its checksum checked.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace levelfuse::io {

/// Bytes of an E57 page, and of its data before the checksum.
inline constexpr std::uint64_t kE57PageBytes = 1024;
inline constexpr std::uint64_t kE57PageDataBytes = 1020;

/// The header at the start of an E57 file.
struct E57Header {
  std::uint32_t majorVersion = 0, minorVersion = 0;
  std::uint64_t physicalLength = 0;     ///< the file's size in bytes
  std::uint64_t xmlPhysicalOffset = 0;  ///< where the XML section starts
  std::uint64_t xmlLogicalLength = 0;   ///< its length, checksums left out
  std::uint64_t pageSize = 0;
};

class E57PagedFile {
 public:
  /// Opens the file at `path` and reads its header. Throws InputError naming
  /// the file for a file that is not a whole number of pages, a first page
  /// whose checksum fails, a signature other than "ASTM-E57", a major version
  /// other than 1, a page size other than 1024, a length other than the
  /// file's, and an XML section beyond the file.
  explicit E57PagedFile(const std::string& path);

  const std::string& path() const { return mPath; }
  const E57Header& header() const { return mHeader; }
  /// Logical bytes in the file (its pages without their checksums).
  std::uint64_t logicalLength() const { return mPages * kE57PageDataBytes; }
  /// The logical offset of a physical one. Throws InputError naming `what`
  /// if it points into a checksum or beyond the file.
  std::uint64_t logicalOffset(std::uint64_t physical, const std::string& what) const;
  /// Reads `size` logical bytes from logical offset `logical` into `out`.
  /// Throws InputError naming `what` if they run past the end of the file,
  /// and naming the page if its checksum fails.
  void read(std::uint64_t logical, std::size_t size, unsigned char* out, const std::string& what);

 private:
  void loadPage(std::uint64_t page);

  std::string mPath;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> mFile;
  std::uint64_t mPages = 0;
  E57Header mHeader;
  std::vector<unsigned char> mPage;
  std::uint64_t mLoadedPage;
};

}  // namespace levelfuse::io
