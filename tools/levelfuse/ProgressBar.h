// levelfuse CLI: a progress line with an estimate of the time left, on a
// terminal only.
#pragma once

#include <levelfuse/recon/Reconstructor.h>

#include <string>
#include <vector>

namespace levelfuse::cli {

class ProgressBar {
 public:
  /// Draws on standard error if `enabled` and standard error is a terminal.
  explicit ProgressBar(bool enabled);
  ~ProgressBar();
  void update(const ReconstructionProgress& p);
  /// Clears the line.
  void finish();

 private:
  double estimateRemaining(const ReconstructionProgress& p) const;

  bool mActive = false;
  std::size_t mLastWidth = 0;
  double mLastDraw = -1.0;
  int mLevel = -1;
  double mLevelStart = 0.0;
  int mLastIteration = 0;
  int mIterationsOfLastLevel = 0;
  double mSecondsPerIteration = 0.0;
};

}  // namespace levelfuse::cli
