// levelfuse: a shaded picture of a level set, to look at instead of read.
#pragma once

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// A camera placed in the world, e.g. inside a scene where a depth camera stood.
struct PreviewCamera {
  openvdb::Vec3d eye{0.0};                ///< the centre of projection (world)
  openvdb::Vec3d forward{0.0, 0.0, -1.0};  ///< the optical axis (world)
  openvdb::Vec3d up{0.0, 1.0, 0.0};        ///< world direction that is up in the picture
};

struct PreviewOptions {
  int width = 800, height = 600;
  /// Direction from the surface's centre toward the camera (world); the
  /// default is a three-quarter view from the front (+z), right and above (+y).
  openvdb::Vec3d toward{0.55, 0.45, 1.0};
  openvdb::Vec3d up{0.0, 1.0, 0.0};  ///< world direction that is up in the picture
  /// Across the picture's height.
  double fieldOfViewDegrees = 30.0;
  /// Where the camera stands; none: outside the surface, looking at it from
  /// `toward` and framing its narrow band (an object). `toward` and `up` are
  /// then unused.
  std::optional<PreviewCamera> camera;
  /// Where this grid (sampled trilinearly at the surface, world units) is below
  /// `minWeight`, the surface is not drawn and rays pass through it: the parts
  /// of a scene no scan observed (recon/SurfaceWeight.h). None: all is drawn.
  openvdb::FloatGrid::ConstPtr weight;
  double minWeight = 0.0;
  /// The surface's colour where given (a "Cd" grid: scan/SurfaceColour.h,
  /// sampled at the surface by colourAt), else a warm light grey.
  openvdb::Vec3fGrid::ConstPtr colour;
};

/// `options` seen through a depth frame's camera: its pose, its vertical field
/// of view, and a picture of the options' width with the frame's aspect. For
/// a scene, whose surfaces a camera that saw them stood among. A spherical
/// scanner's view is a camera at the scanner looking level toward the middle
/// of its sweep, its z axis up, 60 degrees high at the options' width and
/// height. Throws std::invalid_argument for an orthographic map.
PreviewOptions seenByFrame(const RangeMap& frame, PreviewOptions options = {});

/// An 8-bit RGB picture, row-major from the top left, three bytes a pixel.
struct PreviewImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

/// Ray-casts the zero set of `levelSet` with a perspective camera (framed on
/// its narrow band, or the options' camera) and shades it with two lights.
/// Throws std::invalid_argument for a grid that is not a level set or has no
/// surface, or a picture size or field of view out of range.
PreviewImage renderPreview(const openvdb::FloatGrid& levelSet, const PreviewOptions& options = {});

/// The picture of renderPreview as an 8-bit RGB PNG, written atomically;
/// std::runtime_error names `path` if it cannot be written.
void writePreviewPng(const openvdb::FloatGrid& levelSet, const std::string& path, const PreviewOptions& options = {});
/// The same, as one of a run's outputs: committed with the others (AtomicWrite.h).
void writePreviewPng(OutputSet& outputs, const openvdb::FloatGrid& levelSet, const std::string& path,
                     const PreviewOptions& options = {});

}  // namespace levelfuse::io
