// levelfuse: the options of loading scans (loadScans), which every reader of
// scans takes: the noise and depth settings of each kind of scan, the
// interrupter and the progress, which scans are wanted and what takes them as
// they are read.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/io/scans/LoadProgress.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/scan/RangeMap.h>

#include <cstddef>
#include <functional>
#include <limits>

namespace levelfuse::io {

/// Takes each scan as soon as it is read (ScanLoadOptions::take).
using ScanTaker = std::function<void(RangeMap&&)>;

struct ScanLoadOptions {
  StanfordScanOptions stanford;  ///< for .conf files: the scanner's direction, sigma, pixel size
  /// Metres per unit of 16-bit depth PNGs; 0 takes the convention's: 0.001
  /// (millimetres: 7-Scenes, manifests), 1/5000 for TUM RGB-D folders.
  double depthScale = 0.0;
  DepthNoise depthNoise;         ///< sigma of depth-camera readings
  int frameStride = 1;           ///< of a folder of depth frames, every n-th
  Interrupter interrupter;       ///< asked before each scan or frame is read (Interrupted)
  /// Told after each scan or frame is read (of a manifest: after each entry),
  /// with how many of how many are in.
  LoadProgress progress;
  /// Depth readings deeper than this (metres) are dropped; positive.
  double maxDepth = std::numeric_limits<double>::infinity();
  /// TUM RGB-D folders: a frame takes the pose of the nearest timestamp, which
  /// must lie within this many seconds of the frame's.
  double poseTimeTolerance = 0.02;
  /// Noise of a terrestrial station's readings (PTX and E57 scans; metres).
  /// 2 mm by default: the order of a terrestrial laser scanner's range noise
  /// at tens of metres; give the scanner's own where it is known.
  double stationSigma = 0.002;
  /// Noise of the readings of a point cloud binned into a range map (a
  /// manifest's `points` and `kitti-bin` entries, E57 scans without a grid;
  /// metres), 2 mm by default as for stations.
  double pointSigma = 0.002;
  /// Gives every reading the same noise `sigma` (world units), whatever the
  /// scan: Stanford scans' sigma, depth frames' noise, stations' and point
  /// clouds' alike.
  void setSigma(double sigma) {
    stanford.sigma = sigma;
    depthNoise = DepthNoise{sigma, 0.0};
    stationSigma = sigma;
    pointSigma = sigma;
  }

  /// If set, asked once for every scan, in order, with its place among the
  /// scans of the path (from 0): a scan it turns down is neither handed over
  /// nor kept. The frames of a folder are asked before any is read, and
  /// those turned down are not read, as are the scans of a .conf file and a
  /// manifest's entries of one scan; other scans are asked as each is read.
  /// (The processes of a team each read their part of the scans.)
  std::function<bool(std::size_t)> wanted;

  /// If set, each scan is handed over as soon as it is read instead of
  /// collected, and loadScans returns none: a folder of depth frames is then
  /// read holding one frame at a time (Stanford and manifest scans, a few,
  /// are handed over once all are read).
  ScanTaker take;
  /// The memory the readers may allocate: each refuses, before it allocates,
  /// a scan that would need more (InputError). The machine's by default.
  MemoryBudget memoryBudget;
};

}  // namespace levelfuse::io
