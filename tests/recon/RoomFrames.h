// Depth frames of a synthetic room, for the tests of depth-video reconstruction.
#pragma once

#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/synth/Synth.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace levelfuse {

using openvdb::Vec3d;

/// A room 4 m wide (walls, floor and ceiling solid, the inside empty) with a
/// box of 30 cm standing on its floor and a shelf 4 cm thick on one wall:
/// negative inside solid, 1-Lipschitz.
inline double roomSignedDistance(const Vec3d& x) {
  const auto box = [&](const Vec3d& centre, const Vec3d& half) {
    const Vec3d q(std::fabs(x.x() - centre.x()) - half.x(), std::fabs(x.y() - centre.y()) - half.y(),
                  std::fabs(x.z() - centre.z()) - half.z());
    const Vec3d outside(std::max(q.x(), 0.0), std::max(q.y(), 0.0), std::max(q.z(), 0.0));
    return outside.length() + std::min(std::max(q.x(), std::max(q.y(), q.z())), 0.0);
  };
  const double room = std::min({2.0 - std::fabs(x.x()), 1.5 - std::fabs(x.y()), 2.0 - std::fabs(x.z())});
  const double object = box(Vec3d(0.3, -1.35, 0.8), Vec3d(0.15, 0.15, 0.15));
  const double shelf = box(Vec3d(-0.5, 0.2, 1.95), Vec3d(0.6, 0.02, 0.15));
  return std::min({room, object, shelf});
}

/// Depth frames from eyes on an arc in the room's near half, all looking at
/// the far wall: every surface is seen from one side only. Even positions
/// reconstruct, odd ones are held out.
struct RoomFrames {
  std::vector<RangeMap> reconstruction, heldOut;
};

inline RoomFrames roomFrames() {
  RoomFrames frames;
  synth::Noise noise;
  noise.gaussianSigma = 0.005;
  for (int i = 0; i < 16; ++i) {
    const double a = -0.6 + 1.2 * i / 15.0;
    const Vec3d eye(1.2 * std::sin(a), 0.2 * std::cos(3.0 * a), -1.2 + 0.3 * std::cos(a));
    const Vec3d target(0.3 * std::sin(2.0 * a), -0.6, 1.5);
    synth::View view = synth::pinholeView(eye, target, 70.0, 80, 60, "frame " + std::to_string(i));
    noise.seed = static_cast<std::uint64_t>(i + 1);
    (i % 2 == 0 ? frames.reconstruction : frames.heldOut)
        .push_back(synth::renderDistanceFunction(roomSignedDistance, view, noise, 0.005));
  }
  return frames;
}

}  // namespace levelfuse
