// levelfuse: a spinning LiDAR's sweep, listed laser after laser in the order
// its lasers fired, as spherical range maps.
//
// A spinning LiDAR (a Velodyne HDL-64E, as KITTI recorded it) has one laser
// per row of its rays. Each laser sweeps a cone about the sensor's z axis
// whose apex lies on that axis but not at the sensor's origin: the HDL-64E's
// two blocks of lasers sit about 12 and 20 cm above it. Seen from the origin,
// a laser's near returns rise by that height over their distance (two
// degrees at 5 m), so binned by their directions from the origin the returns
// of neighbouring lasers overlap by several rows and fight over pixels.
// KITTI's files list a sweep laser by laser, each over one turn from where
// the sweep was cut, in firing order: the lasers are found from that order,
// each laser's cone is fitted to its returns, and the lasers that share an
// apex become one range map seen from it, a laser to a row and a firing to a
// column, so that no two returns share a pixel.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <optional>
#include <string>
#include <vector>

namespace levelfuse {

/// The cone of one laser's rays: its apex on the sensor's z axis and the
/// angle of its rays above the plane through the apex square to that axis.
struct LaserCone {
  double apexHeight = 0.0;  ///< metres along the sensor's z axis
  double elevation = 0.0;   ///< radians
};

/// A sweep's returns by laser (lasersInFiringOrder).
struct LaserRows {
  std::vector<int> laserOfPoint;  ///< per point, its laser; -1 for no return or one whose laser is unknown
  std::vector<LaserCone> lasers;  ///< in the order they fired
  double cut = 0.0;               ///< the azimuth at which each laser's turn begins (radians)
  double azimuthStep = 0.0;       ///< the mean turn between consecutive firings (radians, signed as the sensor spins)
};

/// Lasers whose cones' apexes lie closer than this (metres) share one range
/// map (sweepRangeMaps).
inline constexpr double kSharedApex = 0.02;

/// The lasers of a sweep whose points (in the sensor's frame, z up) are
/// listed laser after laser, each over one turn of the sensor, in firing
/// order (KITTI's velodyne files): a laser's turn ends where the order
/// crosses the azimuth at which the sweep was cut, each point near a crossing
/// going to the laser on whose cone it lies, and each laser's cone is fitted
/// to its points (least squares, then again without points more than five
/// times the median misfit off). None unless the points are in that order:
/// at least four turns, turning one way, each laser's cone fitting its points
/// within a tenth of the typical spacing between lasers. A laser with fewer
/// than 16 returns keeps none (-1).
std::optional<LaserRows> lasersInFiringOrder(const std::vector<openvdb::Vec3d>& points);

/// The sweep as spherical range maps, one for each block of lasers whose
/// apexes lie within kSharedApex of each other (a block of one laser joins
/// the block with the nearest apex): the map's scanner at the block's mean
/// apex (`sensorToWorld` moved up the sensor's z axis), its rows the block's
/// lasers by their elevation seen from there, its columns a turn of the
/// firings' mean step, starting at the cut (a closed turn where every column
/// has a return, else the arc the returns span). Each return goes to its
/// laser's row and the column of its azimuth, or, where the laser's previous
/// firing took that column, the next one if it lies within a column of it;
/// its reading is its distance from the map's scanner, moved to its pixel's
/// centre along the neighbouring readings (as sphericalMapFromPoints does).
/// Each reading has noise `sigma`; maps are named `name` and their lasers
/// ("000000.bin, lasers 1-32"). Throws std::invalid_argument if a block's
/// lasers do not have distinct elevations.
std::vector<RangeMap> sweepRangeMaps(const std::vector<openvdb::Vec3d>& points, const LaserRows& lasers,
                                     const openvdb::math::Mat4d& sensorToWorld, double sigma,
                                     const std::string& name);

}  // namespace levelfuse
