// levelfuse: reading a .vdb file's bytes, each read checked first.

#include "VdbByteReader.h"

#include <levelfuse/io/InputError.h>

#include <system_error>
#include <filesystem>

namespace levelfuse::io::detail {

VdbByteReader::VdbByteReader(const std::string& path) : mPath(path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, "cannot read the file's size (" + excerpt(ec.message()) + ")");
  mSize = static_cast<std::uint64_t>(size);
  mFile.open(path, std::ios::in | std::ios::binary);
  if (!mFile) throw InputError(path, "cannot be opened");
}

void VdbByteReader::require(std::uint64_t bytes, const char* what) const {
  if (bytes > remaining())
    fail(std::string("the file ends in ") + what + " (" + std::to_string(bytes) + " bytes needed, " +
         std::to_string(remaining()) + " left; truncated?)");
}

void VdbByteReader::read(void* data, std::uint64_t bytes, const char* what) {
  require(bytes, what);
  if (!mFile.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes)))
    fail(std::string("cannot read ") + what + " (the file changed while it was read?)");
  mPosition += bytes;
}

void VdbByteReader::skip(std::uint64_t bytes, const char* what) {
  require(bytes, what);
  if (bytes == 0) return;
  mPosition += bytes;
  if (!mFile.seekg(static_cast<std::streamoff>(mPosition)))
    fail(std::string("cannot read ") + what + " (the file changed while it was read?)");
}

void VdbByteReader::seek(std::uint64_t offset, const char* what) {
  if (offset > mSize)
    fail(std::string(what) + " is byte " + std::to_string(offset) + ", beyond the file's " +
         std::to_string(mSize) + " bytes (truncated?)");
  mPosition = offset;
  if (!mFile.seekg(static_cast<std::streamoff>(mPosition)))
    fail(std::string("cannot read ") + what + " (the file changed while it was read?)");
}

void VdbByteReader::fail(const std::string& problem) const {
  throw InputError(mPath, "not a valid .vdb file: " + (mContext.empty() ? std::string() : mContext + ": ") +
                              problem + " (at byte " + std::to_string(mPosition) + ")");
}

}  // namespace levelfuse::io::detail
