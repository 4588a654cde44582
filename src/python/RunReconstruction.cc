// levelfuse Python module: a reconstruction run as the converter runs it,
// and what its summary measures.

#include "Result.h"

#include <levelfuse/recon/ScansReconstruction.h>

#include <chrono>

namespace levelfuse::python {

Outcome runReconstruction(const Reconstructor& reconstructor, const RangeMapSequence& scans,
                          const RunSettings& settings, const ProgressCallback& progress,
                          const Interrupter& interrupter, const std::function<RangeMapSequence()>& beforeFit) {
  const auto started = std::chrono::steady_clock::now();
  Outcome o;
  o.linear = settings.linear;
  o.inputs = settings.inputs;
  o.settings = reconstructor.settings();
  o.scans = reconstructor.summary().scans();
  o.readings = reconstructor.summary().readings();
  o.points = reconstructor.summary().points();
  o.scene = reconstructor.summary().aScene();
  if (settings.linear) o.result.levelSet = reconstructor.linearSolution(interrupter);
  else o.result = reconstructor.run(progress, interrupter);
  if (!o.result.weight) o.result.weight = reconstructor.surfaceWeight(*o.result.levelSet, interrupter);
  if (settings.linear) o.result.colour = reconstructor.surfaceColour(*o.result.levelSet, interrupter);
  describeInputs(*o.result.levelSet, settings.inputs, settings.linear, o.scene);
  const RangeMapSequence fitScans = beforeFit ? beforeFit() : scans;
  if (settings.fit) {
    o.fitStride = fitStride(fitScans, kFitPointsAtMost);
    o.fit = measureDataFit(*o.result.levelSet, fitScans, o.fitStride);
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return o;
}

}  // namespace levelfuse::python
