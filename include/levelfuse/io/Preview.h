// levelfuse: a shaded picture of a level set, to look at instead of read.
#pragma once

#include <levelfuse/io/AtomicWrite.h>

#include <openvdb/openvdb.h>

#include <string>

namespace levelfuse::io {

struct PreviewOptions {
  int width = 800, height = 600;
  /// Direction from the surface's centre toward the camera (world); the
  /// default is a three-quarter view from the front (+z), right and above (+y).
  openvdb::Vec3d toward{0.55, 0.45, 1.0};
  openvdb::Vec3d up{0.0, 1.0, 0.0};  ///< world direction that is up in the picture
  double fieldOfViewDegrees = 30.0;
};

/// Ray-casts the zero set of `levelSet` with a perspective camera framed on its
/// narrow band, shades it with two lights, and writes an 8-bit RGB PNG
/// atomically. Throws std::invalid_argument for a grid that is not a level set
/// or has no surface, std::runtime_error naming `path` if it cannot be written.
void writePreviewPng(const openvdb::FloatGrid& levelSet, const std::string& path, const PreviewOptions& options = {});
/// The same, as one of a run's outputs: committed with the others (AtomicWrite.h).
void writePreviewPng(OutputSet& outputs, const openvdb::FloatGrid& levelSet, const std::string& path,
                     const PreviewOptions& options = {});

}  // namespace levelfuse::io
