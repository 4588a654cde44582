// levelfuse CLI: small things the subcommands share.
#pragma once

#include <openvdb/math/Vec3.h>
#include <tbb/global_control.h>

#include <cstddef>
#include <memory>
#include <string>

namespace levelfuse::cli {

/// Limits TBB to `threads` workers for its lifetime (0: all cores).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);

 private:
  std::unique_ptr<tbb::global_control> mControl;
};

/// The process's peak resident memory so far, in bytes.
std::size_t peakResidentBytes();

/// Throws std::runtime_error naming `path` if a file cannot be created there
/// (its folder is missing or not writable): checked before long work.
void requireWritable(const std::string& path);

/// "1,234,567"
std::string withCommas(std::size_t n);
/// A number with `digits` significant digits.
std::string fixed(double value, int digits = 4);
/// `text` with control characters (a file's bytes quoted in a message) as \xNN:
/// one line, safe for a terminal.
std::string printable(const std::string& text);
/// "12.3 MiB"
std::string mebibytes(std::size_t bytes);
/// Parses "x,y,z" into a vector; throws std::invalid_argument otherwise.
openvdb::math::Vec3d parseVec3(const std::string& text);

}  // namespace levelfuse::cli
