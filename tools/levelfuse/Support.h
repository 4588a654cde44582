// levelfuse CLI: small things the subcommands share.
#pragma once

#include <levelfuse/core/PeakMemory.h>
#include <levelfuse/io/AtomicWrite.h>

#include <CLI/CLI.hpp>
#include <openvdb/math/Vec3.h>
#include <tbb/global_control.h>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse::cli {

/// Limits TBB to `threads` workers for its lifetime (0: all cores).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);

 private:
  std::unique_ptr<tbb::global_control> mControl;
};

/// A number option's check: a finite number from `lo` to `hi` (above `lo` if
/// `aboveLo`); NaN and infinities are refused (exit 2). The description that
/// --help prints states the range.
CLI::Validator numberIn(double lo, double hi, bool aboveLo = false);

/// A vector option's check: three finite numbers x,y,z (parseVec3).
CLI::Validator threeNumbers();

/// Before any work: throws std::runtime_error unless every non-empty path of
/// `outputs` can be written (io::requireWritable) and none is one of `inputs`
/// (io::refuseOverwritingInputs).
void requireOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs);

/// The end of a run: refuses outputs that are among the files the readers
/// read (io::inputsRead()), stops if a cancellation is pending, then commits.
void commitOutputs(io::OutputSet& outputs);

/// --trim-unseen and --no-trim-unseen on `cmd`: set `trim` to true or false;
/// left empty, the command decides. For --help: `outputs` says what is
/// trimmed ("Mesh"), `byDefault` when. `trim` must outlive the parsing.
void addTrimUnseenOptions(CLI::App* cmd, std::optional<bool>& trim, const std::string& outputs,
                          const std::string& byDefault);

/// "1,234,567"
std::string withCommas(std::size_t n);
/// The items, separated by commas (file names in a message).
std::string joined(const std::vector<std::string>& items);
/// A number with `digits` significant digits.
std::string fixed(double value, int digits = 4);
/// "12.3 MiB"
std::string mebibytes(std::size_t bytes);
/// Parses "x,y,z" into a vector; throws std::invalid_argument otherwise.
openvdb::math::Vec3d parseVec3(const std::string& text);

}  // namespace levelfuse::cli
