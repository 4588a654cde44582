// Six noisy views of a torus.

#include "support/NoisyTorus.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/synth/Synth.h>

namespace levelfuse::test {

std::vector<RangeMap> noisyTorusScans() {
  const shapes::Torus torus{openvdb::Vec3d(0.013, -0.021, 0.007), 0.8, 0.3};
  std::vector<RangeMap> maps;
  std::uint64_t seed = 1;
  for (const synth::View& view : synth::sixAxisViews(openvdb::Vec3d(0.0), 2.4, 120)) {
    synth::Noise noise;
    noise.gaussianSigma = 0.01;
    noise.seed = seed++;
    maps.push_back(synth::renderDistanceFunction(torus, view, noise, 0.01));
  }
  return maps;
}

}  // namespace levelfuse::test
