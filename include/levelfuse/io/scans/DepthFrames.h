// levelfuse: depth frames read with the options of loading scans (their
// depth scale, maximum depth and noise), as the readers of folders of depth
// frames read them.
#pragma once

#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Mat4.h>

#include <string>

namespace levelfuse::io {

/// One depth frame (a 16-bit PNG, PFM or EXR) as a pinhole range map, with
/// the options' depth scale (`conventionScale` if it is 0), maximum depth and
/// noise; named after the image's file name.
RangeMap loadDepthFrame(const std::string& image, const PinholeProjection& intrinsics,
                        const openvdb::math::Mat4d& cameraToWorld, const ScanLoadOptions& options,
                        double conventionScale);

/// Throws InputError naming `source` if the options' frame stride, maximum
/// depth or depth scale are out of range.
void checkDepthOptions(const ScanLoadOptions& options, const std::string& source);

}  // namespace levelfuse::io
