// The converter's tests' ball: a ball of radius 0.5 at the origin seen by
// eight scanners 2 m away around it, and what info and reconstruct must say
// of it, whatever files its scans come in (PtxCliTest, PointsCliTest).
#pragma once

#include "CliSupport.h"
#include "support/PtxFiles.h"

#include <openvdb/Types.h>

#include <string>
#include <vector>

namespace levelfuse::test {

inline constexpr double kBallRadius = 0.5;
inline constexpr double kScannerDistance = 2.0;
inline constexpr int kBallScanners = 8;

/// Scanner `k` of eight around the ball, every other one above it and the
/// others below (45 degrees up or down), level and looking at it; its scan
/// 51 x 51 rays about 0.012 rad apart (512 a turn) about the ball.
PtxGrid ballScannerGrid(int k);

/// Scanner `k`'s points on the ball in its frame, column after column; the
/// origin where a ray misses.
std::vector<openvdb::Vec3d> ballScanPoints(const PtxGrid& grid);

/// Expects `info --json` of the eight scans: scanner 2's position, and
/// readings that lie on the ball (within `tolerance`).
void expectBallInfo(const nlohmann::json& info, double tolerance);

/// Expects `reconstruct --voxel-size 0.02 --trim-unseen --json` of the eight
/// scans: a fit within half a voxel and a mesh at `meshPath` on the ball.
void expectBallReconstruction(const CliRun& run, const std::string& meshPath);

}  // namespace levelfuse::test
