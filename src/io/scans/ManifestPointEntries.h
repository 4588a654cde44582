// levelfuse: a manifest's point-cloud entries, `points` and `kitti-bin`
// (private to the manifest reader; the fields are described in Manifest.h).
#pragma once

#include "ManifestEntry.h"

#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/scan/RangeMap.h>

#include <vector>

namespace levelfuse::io {

/// A `points` entry: an XYZ or PLY file with the sensor's "origin" or
/// "pose" (or "pose_file"), its points in the world ("coordinates": "world",
/// the default) or in the sensor's frame ("sensor"), as one spherical range
/// map with the entry's "azimuth_step" and "elevation_step" (degrees; both or
/// neither: estimated from the points) and "sigma" (else the options').
RangeMap loadPointsEntry(const Entry& e, const ScanLoadOptions& defaults);

/// A `kitti-bin` entry: a KITTI velodyne sweep with its velodyne-to-world
/// "pose" (or "pose_file"), or with KITTI odometry's "poses" file, "calib"
/// file and "frame" index. Without angular steps, a sweep listed laser by
/// laser in firing order, as KITTI's are, becomes a range map per block of
/// lasers that share an apex (lasersInFiringOrder, sweepRangeMaps); with
/// them, or in another order, one spherical range map (steps and sigma as
/// for `points`).
std::vector<RangeMap> loadKittiBinEntry(const Entry& e, const ScanLoadOptions& defaults);

}  // namespace levelfuse::io
