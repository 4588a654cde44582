// levelfuse: an E57 file's header and checked pages.

#include "E57PagedFile.h"

#include "../ByteOrder.h"
#include "Crc32c.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>

namespace levelfuse::io {

namespace {

constexpr char kSignature[] = "ASTM-E57";
constexpr std::size_t kSignatureBytes = 8;
constexpr std::size_t kHeaderBytes = 48;
constexpr std::uint64_t kNoPage = std::numeric_limits<std::uint64_t>::max();

/// The file's size, a positive whole number of pages.
std::uint64_t pagedSize(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, "cannot tell the file's size (" + ec.message() + ")");
  if (bytes < kHeaderBytes)
    throw InputError(path, "a file of " + std::to_string(bytes) + " bytes is too short for an E57 file's " +
                               std::to_string(kHeaderBytes) + "-byte header: truncated, or not an E57 file");
  if (bytes % kE57PageBytes != 0)
    throw InputError(path, "a size of " + std::to_string(bytes) + " bytes is not a whole number of E57's " +
                               std::to_string(kE57PageBytes) + "-byte pages: truncated?");
  return bytes;
}

/// Refuses a file that does not start with E57's signature, before its
/// first page's checksum is checked: another kind of file is named as such.
void requireSignature(std::FILE* file, const std::string& path) {
  char start[kSignatureBytes] = {};
  if (std::fread(start, 1, kSignatureBytes, file) != kSignatureBytes)
    throw InputError(path, "cannot read its first bytes (an input/output error)");
  if (std::memcmp(start, kSignature, kSignatureBytes) != 0)
    throw InputError(path, "not an E57 file: it starts with " + quote(std::string(start, kSignatureBytes)) +
                               ", not 'ASTM-E57'");
}

E57Header parseHeader(const unsigned char* bytes, const std::string& path) {
  E57Header h;
  h.majorVersion = static_cast<std::uint32_t>(detail::littleEndianUnsigned(bytes + 8, 4));
  h.minorVersion = static_cast<std::uint32_t>(detail::littleEndianUnsigned(bytes + 12, 4));
  h.physicalLength = detail::littleEndianUnsigned(bytes + 16, 8);
  h.xmlPhysicalOffset = detail::littleEndianUnsigned(bytes + 24, 8);
  h.xmlLogicalLength = detail::littleEndianUnsigned(bytes + 32, 8);
  h.pageSize = detail::littleEndianUnsigned(bytes + 40, 8);
  if (h.majorVersion != 1)
    throw InputError(path, "E57 version " + std::to_string(h.majorVersion) + "." + std::to_string(h.minorVersion) +
                               ": levelfuse reads version 1 (ASTM E2807)");
  if (h.pageSize != kE57PageBytes)
    throw InputError(path, "the header gives a page size of " + std::to_string(h.pageSize) +
                               " bytes; E57 pages are " + std::to_string(kE57PageBytes));
  return h;
}

}  // namespace

E57PagedFile::E57PagedFile(const std::string& path)
    : mPath(path), mFile(nullptr, &std::fclose), mPage(kE57PageBytes), mLoadedPage(kNoPage) {
  requireInputFile(path);
  const std::uint64_t bytes = pagedSize(path);
  mPages = bytes / kE57PageBytes;
  mFile.reset(std::fopen(path.c_str(), "rb"));
  if (!mFile) throw InputError(path, "cannot be opened for reading");
  requireSignature(mFile.get(), path);
  loadPage(0);
  mHeader = parseHeader(mPage.data(), path);
  if (mHeader.physicalLength != bytes)
    throw InputError(path, "the header says the file is " + std::to_string(mHeader.physicalLength) +
                               " bytes long; it is " + std::to_string(bytes) + " (truncated?)");
  const std::uint64_t xml = logicalOffset(mHeader.xmlPhysicalOffset, "the XML section");
  if (mHeader.xmlLogicalLength == 0 || mHeader.xmlLogicalLength > logicalLength() - xml)
    throw InputError(path, "the header places an XML section of " + std::to_string(mHeader.xmlLogicalLength) +
                               " bytes at byte " + std::to_string(mHeader.xmlPhysicalOffset) +
                               ", beyond the file's " + std::to_string(bytes) + " bytes");
}

std::uint64_t E57PagedFile::logicalOffset(std::uint64_t physical, const std::string& what) const {
  if (physical >= mPages * kE57PageBytes)
    throw InputError(mPath, what + " is placed at byte " + std::to_string(physical) + ", beyond the file's " +
                                std::to_string(mPages * kE57PageBytes) + " bytes");
  if (physical % kE57PageBytes >= kE57PageDataBytes)
    throw InputError(mPath, what + " is placed at byte " + std::to_string(physical) +
                                ", inside the checksum of page " + std::to_string(physical / kE57PageBytes));
  return physical / kE57PageBytes * kE57PageDataBytes + physical % kE57PageBytes;
}

void E57PagedFile::read(std::uint64_t logical, std::size_t size, unsigned char* out, const std::string& what) {
  if (logical > logicalLength() || size > logicalLength() - logical)
    throw InputError(mPath, what + " runs past the end of the file (" + std::to_string(size) + " bytes from byte " +
                                std::to_string(logical) + " of its " + std::to_string(logicalLength()) +
                                " without checksums): truncated, or an offset that is wrong");
  while (size > 0) {
    loadPage(logical / kE57PageDataBytes);
    const std::size_t within = static_cast<std::size_t>(logical % kE57PageDataBytes);
    const std::size_t take = std::min<std::size_t>(size, kE57PageDataBytes - within);
    std::memcpy(out, mPage.data() + within, take);
    out += take;
    logical += take;
    size -= take;
  }
}

void E57PagedFile::loadPage(std::uint64_t page) {
  if (page == mLoadedPage) return;
  mLoadedPage = kNoPage;
  if (std::fseek(mFile.get(), static_cast<long>(page * kE57PageBytes), SEEK_SET) != 0 ||
      std::fread(mPage.data(), 1, kE57PageBytes, mFile.get()) != kE57PageBytes)
    throw InputError(mPath, "cannot read page " + std::to_string(page) + " (an input/output error, or the file "
                                                                        "shrank while it was read)");
  const std::uint32_t stored = detail::bigEndian32(mPage.data() + kE57PageDataBytes);
  const std::uint32_t computed = detail::crc32c(mPage.data(), kE57PageDataBytes);
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
  const bool checked = false;  // the fuzzers reach past the checksums, as is customary
#else
  const bool checked = true;
#endif
  if (checked && stored != computed)
    throw InputError(mPath, "page " + std::to_string(page) + " (bytes " + std::to_string(page * kE57PageBytes) +
                                " to " + std::to_string((page + 1) * kE57PageBytes - 1) +
                                ") fails its CRC-32C checksum: the file is damaged");
  mLoadedPage = page;
}

}  // namespace levelfuse::io
