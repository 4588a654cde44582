// A folder of depth video as the 7-Scenes folders in ../shared/data hold it
// (frame-NNNNNN.depth.png, frame-NNNNNN.pose.txt, camera-intrinsics.txt), and
// the frames of it held out from a reconstruction to measure it by.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <string>
#include <vector>

namespace levelfuse::bench {

/// The folder's frames, sorted: their paths without ".depth.png".
std::vector<std::string> frameStems(const std::string& folder);

/// The frames at positions offset, offset + every, ... of the folder's sorted
/// frames, as levelfuse reads them (pinhole range maps in world space).
std::vector<RangeMap> heldOutFrames(const std::string& folder, int every, int offset);

}  // namespace levelfuse::bench
