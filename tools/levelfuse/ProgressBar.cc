#include "ProgressBar.h"

#include "Support.h"
#include "Units.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

namespace levelfuse::cli {

ProgressBar::ProgressBar(bool enabled) : mActive(enabled && ::isatty(STDERR_FILENO) == 1) {}

ProgressBar::~ProgressBar() { finish(); }

double ProgressBar::estimateRemaining(const ReconstructionProgress& p) const {
  if (mSecondsPerIteration <= 0.0) return -1.0;
  // Iterations still to come on this grid (as many as the last grid needed,
  // or half the limit on the first), then each finer grid: about four times
  // the surface voxels, so four times the cost per iteration.
  const int expected = mIterationsOfLastLevel > 0 ? mIterationsOfLastLevel : p.maxIterations / 2;
  double remaining = std::max(0, expected - p.iteration) * mSecondsPerIteration;
  double perIteration = mSecondsPerIteration;
  for (int level = p.level + 1; level < p.levels; ++level) {
    perIteration *= 4.0;
    remaining += perIteration * expected;
  }
  return remaining;
}

void ProgressBar::update(const ReconstructionProgress& p) {
  if (!mActive) return;
  using Stage = ReconstructionProgress::Stage;
  if (p.level != mLevel) {
    if (mLevel >= 0) mIterationsOfLastLevel = mLastIteration;
    mLevel = p.level;
    mLevelStart = p.seconds;
  }
  if (p.stage == Stage::kEvolving && p.iteration > 0) {
    mLastIteration = p.iteration;
    mSecondsPerIteration = (p.seconds - mLevelStart) / p.iteration;
  }
  const bool counting = p.stage == Stage::kIntegrating || p.stage == Stage::kInitialModel;
  const bool frequent = p.stage == Stage::kEvolving || (counting && p.scan < p.scans);
  std::ostringstream line;
  line << "grid " << p.level + 1 << "/" << p.levels << " (voxel " << length(p.voxelSize) << ") ";
  switch (p.stage) {
    case Stage::kInitialModel:
      line << "initial model";
      if (p.scan > 0) line << ": carving, scan " << p.scan << "/" << p.scans;
      break;
    case Stage::kResampling: line << "resampling"; break;
    case Stage::kIntegrating: line << "integrating scan " << p.scan << "/" << p.scans; break;
    case Stage::kDone: line << "done"; break;
    case Stage::kEvolving:
      line << "iteration " << p.iteration << " | " << withCommas(p.activeSetVoxels) << " in the active set | speed "
           << fixed(p.speed, 2);
      break;
  }
  line << " | " << fixed(p.seconds, 3) << " s";
  const double eta = estimateRemaining(p);
  if (eta >= 0.0 && p.stage != Stage::kDone) line << ", about " << fixed(std::ceil(eta), 3) << " s left";
  draw(line.str(), frequent, p.seconds);
}

void ProgressBar::loading(std::size_t read, std::size_t total) { counting("loading", read, total); }

void ProgressBar::integrating(std::size_t done, std::size_t total) { counting("integrating", done, total); }

void ProgressBar::counting(const char* what, std::size_t done, std::size_t total) {
  if (!mActive) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
  draw(std::string(what) + " scan " + std::to_string(done) + "/" + std::to_string(total) + " | " + fixed(seconds, 3) +
           " s",
       done < total, seconds);
}

void ProgressBar::draw(const std::string& line, bool frequent, double seconds) {
  if (seconds - mLastDraw < 0.1 && frequent) return;  // at most ten lines a second
  mLastDraw = seconds;
  std::string text = line;
  const std::size_t width = text.size();
  if (text.size() < mLastWidth) text += std::string(mLastWidth - text.size(), ' ');
  mLastWidth = width;
  std::cerr << '\r' << text << std::flush;
}

void ProgressBar::finish() {
  if (!mActive || mLastWidth == 0) return;
  std::cerr << '\r' << std::string(mLastWidth, ' ') << '\r' << std::flush;
  mLastWidth = 0;
}

}  // namespace levelfuse::cli
