// levelfuse: a JSON manifest that lists scans with their geometry, pose,
// noise and format, so any scanner can be described without code.
//
//   {
//     "scans": [
//       { "format": "stanford-conf", "file": "bun.conf",
//         "toward_scanner": [0, 0, 1], "sigma": 0.0002 },
//       { "format": "stanford-ply", "file": "bun045.ply",
//         "translation": [-0.052, 0.0, -0.011], "quaternion": [0.0055, -0.29, -0.0039, 0.96] },
//       { "format": "depth-png", "file": "frame-000000.depth.png", "depth_scale": 0.001,
//         "intrinsics_file": "camera-intrinsics.txt", "pose_file": "frame-000000.pose.txt" },
//       { "format": "ptx", "file": "hall.ptx", "sigma": 0.003 },
//       { "format": "e57", "file": "pump.e57" },
//       { "format": "depth-pfm", "file": "d.pfm",
//         "intrinsics": { "fx": 585, "fy": 585, "cx": 320, "cy": 240 },
//         "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
//         "sigma": { "minimum": 0.001, "per_square_metre": 0.0015 } }
//     ]
//   }
//
// Paths are relative to the manifest. Formats: stanford-conf, stanford-ply,
// depth-png, depth-pfm, depth-exr (each may say "max_depth" in metres: deeper
// readings are dropped), tum (a TUM RGB-D "folder", see TumScans.h, with
// optional "depth_scale", "max_depth", "frame_stride" and "sigma" as for
// depth-pfm), ptx (a PTX file of one or more terrestrial laser scans, see
// PtxScans.h, with an optional "sigma" in metres; without one, the loader's
// ScanLoadOptions::stationSigma, 0.002 by default), e57 (an E57 file of one or
// more scans, see E57Scans.h, with an optional "sigma" as for ptx), points (an XYZ or PLY point
// cloud with its sensor's "origin" [x, y, z] or "pose"; "coordinates": "world"
// or "sensor"; optional "azimuth_step" and "elevation_step" in degrees, else
// estimated, and "sigma", else ScanLoadOptions::pointSigma), kitti-bin (a KITTI
// velodyne sweep with its "pose", or KITTI odometry's "poses" file, "calib"
// file and "frame"; steps and sigma as for points; see PointScans.h; these two
// refuse fields they do not know), and orthographic-pfm (a range
// map of parallel rays: "pixel_size", "origin" [x, y] of pixel (0, 0) and a "pose"
// from the map's frame, whose rays run along +z, to the world). Poses are
// camera-to-world, 16 numbers in row-major order with the translation in the
// last column. Any entry may say "misses_are_empty": true (a pixel without a
// reading saw nothing on its line of sight; RangeMap::setMissesAreEmpty) with a
// "dropout_reach" in pixels (default 2). An entry of one range map may give it
// colours: "colour": "scan.colour.png", an image of the map's size registered
// to it pixel for pixel (8-bit RGB; grey, palette, 16-bit and alpha PNGs are
// converted), whose colours the reconstruction carries to its surface.
//
// A manifest of synthetic scans may record the shape they show as "truth":
// {"shape": "sphere", "centre": [x, y, z], "radius": r}, {"shape": "torus",
// "centre", "major", "minor"} or {"shape": "mug", "centre", "radius", "height",
// "wall", "handle_bend", "handle_radius"}.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/scan/RangeMap.h>

#include <optional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// Loads every scan a manifest lists; InputError names the manifest and the
/// entry (e.g. "scans[2]: 'pose' needs 16 numbers") or the scan file at fault.
/// The depth scale (if not 0) and maximum depth of `defaults` apply to the
/// depth entries that do not give their own; its interrupter is asked before
/// each entry and scan (Interrupted). With `defaults.wanted`, the scans it
/// picks alone: an entry of one scan not wanted is not read, the scans of an
/// entry of several (a .conf, a TUM folder, a PTX file) are read and those not
/// wanted dropped.
std::vector<RangeMap> loadManifest(const std::string& path, const ScanLoadOptions& defaults = {});

/// The manifest's "truth", if it records one.
std::optional<shapes::AnalyticShape> loadManifestTruth(const std::string& path);

/// Writes range maps as a manifest `directory`/scans.json with one PFM per
/// map beside it (orthographic-pfm or depth-pfm; a pinhole map's sigma is its
/// constant sigma), and the truth if given. The files are committed together
/// (all or none; AtomicWrite.h); the directory is created if need be. Returns
/// the manifest's path.
std::string writeScanSet(const std::string& directory, const std::vector<RangeMap>& maps,
                         const std::optional<shapes::AnalyticShape>& truth = std::nullopt);
/// The same, as outputs of a run: they appear when `outputs` is committed.
std::string writeScanSet(OutputSet& outputs, const std::string& directory, const std::vector<RangeMap>& maps,
                         const std::optional<shapes::AnalyticShape>& truth = std::nullopt);

}  // namespace levelfuse::io
