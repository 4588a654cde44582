// levelfuse: reading a .vdb file's bytes in order, each read checked against
// the bytes left in the file before anything is read or allocated.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace levelfuse::io::detail {

/// A .vdb file read front to back (with seeks), as OpenVDB reads it. Every
/// read says what it reads; when the file ends first, or a check fails, the
/// InputError names the file, the part of the file (context()) and the byte.
class VdbByteReader {
 public:
  /// Opens `path` (a regular file, see requireInputFile).
  explicit VdbByteReader(const std::string& path);

  const std::string& path() const { return mPath; }
  std::uint64_t size() const { return mSize; }
  std::uint64_t position() const { return mPosition; }
  std::uint64_t remaining() const { return mSize - mPosition; }

  /// What is being read, for messages: "grid 'density' (2 of 3)".
  void setContext(const std::string& context) { mContext = context; }

  /// Reads `bytes` bytes of `what`; throws if fewer remain.
  void read(void* data, std::uint64_t bytes, const char* what);
  /// Reads a little-endian value (OpenVDB writes the host's order, which
  /// levelfuse's platforms share).
  template <typename T>
  T read(const char* what) {
    T value{};
    read(&value, sizeof(T), what);
    return value;
  }
  /// Skips `bytes` bytes of `what`; throws if fewer remain.
  void skip(std::uint64_t bytes, const char* what);
  /// Moves to `offset`, which `what` (a grid descriptor's offset) names.
  void seek(std::uint64_t offset, const char* what);
  /// Throws unless `bytes` bytes of `what` remain.
  void require(std::uint64_t bytes, const char* what) const;

  /// Throws InputError: "not a valid .vdb file: <context>: <problem> (at byte N)".
  [[noreturn]] void fail(const std::string& problem) const;

 private:
  std::string mPath, mContext;
  std::ifstream mFile;
  std::uint64_t mSize = 0, mPosition = 0;
};

}  // namespace levelfuse::io::detail
