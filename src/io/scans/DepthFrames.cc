// levelfuse: depth frames read with the options of loading scans (see DepthFrames.h).

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/DepthFrames.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <utility>

namespace levelfuse::io {

void checkDepthOptions(const ScanLoadOptions& options, const std::string& source) {
  if (options.frameStride < 1) throw InputError(source, "the frame stride must be at least 1");
  if (!(options.maxDepth > 0.0)) throw InputError(source, "the maximum depth must be positive");
  if (!(options.depthScale >= 0.0) || !std::isfinite(options.depthScale))
    throw InputError(source, "the depth scale must be positive");
}

RangeMap loadDepthFrame(const std::string& image, const PinholeProjection& intrinsics,
                        const openvdb::math::Mat4d& cameraToWorld, const ScanLoadOptions& options,
                        double conventionScale) {
  DepthImage depth =
      readDepthImage(image, options.depthScale > 0.0 ? options.depthScale : conventionScale, options.memoryBudget);
  dropReadingsBeyond(depth, options.maxDepth);
  try {
    return depthFrame(std::move(depth), intrinsics, cameraToWorld, options.depthNoise,
                      std::filesystem::path(image).filename().string());
  } catch (const std::invalid_argument& e) {  // the frame's geometry: its size against the intrinsics
    throw InputError(image, e.what());
  }
}

}  // namespace levelfuse::io
