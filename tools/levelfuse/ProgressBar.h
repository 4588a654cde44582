// levelfuse CLI: a progress line with an estimate of the time left, on a
// terminal only.
#pragma once

#include <levelfuse/recon/Reconstructor.h>

#include <chrono>
#include <cstddef>
#include <string>

namespace levelfuse::cli {

class ProgressBar {
 public:
  /// Draws on standard error if `enabled` and standard error is a terminal.
  explicit ProgressBar(bool enabled);
  ~ProgressBar();
  /// While the scans are read: "loading scan 17/500 | 3.2 s".
  void loading(std::size_t read, std::size_t total);
  /// While the scans are integrated into the grids: "integrating scan 17/500 | 3.2 s".
  void integrating(std::size_t done, std::size_t total);
  void update(const ReconstructionProgress& p);
  /// Clears the line.
  void finish();

 private:
  double estimateRemaining(const ReconstructionProgress& p) const;
  /// "<what> scan <done>/<total> | <seconds> s".
  void counting(const char* what, std::size_t done, std::size_t total);
  /// Draws `text`, at most ten times a second if `frequent`; `seconds` is the
  /// time the text reports.
  void draw(const std::string& text, bool frequent, double seconds);

  bool mActive = false;
  std::chrono::steady_clock::time_point mStart = std::chrono::steady_clock::now();
  std::size_t mLastWidth = 0;
  double mLastDraw = -1.0;
  int mLevel = -1;
  double mLevelStart = 0.0;
  int mLastIteration = 0;
  int mIterationsOfLastLevel = 0;
  double mSecondsPerIteration = 0.0;
};

}  // namespace levelfuse::cli
