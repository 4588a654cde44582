// Depth frames along a synthetic street (synth::streetScene), for the tests
// of a team whose processes each read the frames their slab needs: each
// frame sees about 2 m of a street 24 m long.
#pragma once

#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/synth/Scenes.h>

#include <vector>

namespace levelfuse {

/// `count` frames of 64 x 48 pixels, with noise of 5 mm.
inline std::vector<RangeMap> streetFrames(int count = 48) {
  synth::SceneOptions options;
  options.views = count;
  options.resolution = 64;
  options.noise = 0.005 / 1.8;
  return synth::streetScene(options).maps;
}

}  // namespace levelfuse
