#include "DepthSequence.h"

#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/recon/HeldOutFrames.h>

#include <algorithm>
#include <filesystem>

namespace levelfuse::bench {

std::vector<std::string> frameStems(const std::string& folder) {
  std::vector<std::string> stems;
  const std::string suffix = ".depth.png";
  for (const std::filesystem::directory_entry& entry : std::filesystem::directory_iterator(folder)) {
    const std::string path = entry.path().string();
    if (path.size() > suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0)
      stems.push_back(path.substr(0, path.size() - suffix.size()));
  }
  std::sort(stems.begin(), stems.end());
  return stems;
}

std::vector<RangeMap> heldOutFrames(const std::string& folder, int every, int offset) {
  const std::vector<std::string> stems = frameStems(folder);
  const PinholeProjection intrinsics = io::readIntrinsics(folder + "/camera-intrinsics.txt");
  std::vector<RangeMap> frames;
  for (const std::size_t i : splitFrames(stems.size(), every, offset).heldOut)
    frames.push_back(io::depthFrame(io::readDepthPng(stems[i] + ".depth.png"), intrinsics,
                                    io::readPose(stems[i] + ".pose.txt"), io::DepthNoise(), stems[i]));
  return frames;
}

}  // namespace levelfuse::bench
