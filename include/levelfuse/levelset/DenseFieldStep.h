// levelfuse: DenseField::step for any speed (see SparseFieldStep.h).
#pragma once

#include <levelfuse/levelset/DenseField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/levelset/TimeStep.h>

#include <levelfuse/core/Parallel.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace levelfuse {

template <typename Speed>
StepResult DenseField::step(const Speed& speed, double maxDt) {
  const openvdb::Coord lo = mBox.min(), hi = mBox.max();
  const int nx = mDim.x();
  std::vector<float> slabMax(static_cast<std::size_t>(nx), 0.0f);
  const float h = static_cast<float>(mDx);

  const auto forEachSlab = [&](const auto& body) {
    parallelFor(static_cast<std::size_t>(nx), mOptions.grainSize, [&](std::size_t begin, std::size_t end) {
      for (std::size_t x = begin; x != end; ++x) body(static_cast<int>(x));
    });
  };

  // Rates at every voxel, from the same stencils and speed as the sparse field.
  const openvdb::math::MapBase& map = *mTransform->baseMap();  // the transform holds it
  forEachSlab([&](int x) {
    const auto& local = localSpeed(speed);  // one slab's points, one task
    Stencil s;
    s.h = h;
    float maxRate = 0.0f;
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int z = lo.z(); z <= hi.z(); ++z) {
        const openvdb::Coord ijk(lo.x() + x, y, z);
        for (int p = 0; p < Stencil::kSize; ++p) {
          const int* d = Stencil::kOffset[p];
          const openvdb::Coord n(std::clamp(ijk.x() + d[0], lo.x(), hi.x()),
                                 std::clamp(ijk.y() + d[1], lo.y(), hi.y()),
                                 std::clamp(ijk.z() + d[2], lo.z(), hi.z()));
          s.u[p] = mValues[index(n)];
        }
        float rate = local(ActivePoint{s, ijk, *mTransform, map});
        if (!std::isfinite(rate)) rate = 0.0f;
        mRates[index(ijk)] = rate;
        maxRate = std::max(maxRate, std::fabs(rate));
      }
    slabMax[static_cast<std::size_t>(x)] = maxRate;
  });

  const double maxSpeed = *std::max_element(slabMax.begin(), slabMax.end());
  const double dt = stableTimeStep(
      TimeStepLimits{mOptions.maxStepChange, mOptions.curvatureStepLimit, mOptions.stiffnessStepLimit}, mDx, maxSpeed,
      speed.curvatureWeight(), speedStiffness(speed), maxDt);

  std::vector<double> slabSumSq(static_cast<std::size_t>(nx), 0.0);
  std::vector<float> slabMaxChange(static_cast<std::size_t>(nx), 0.0f);
  const float fdt = static_cast<float>(dt);
  const std::size_t slabSize = static_cast<std::size_t>(mDim.y()) * static_cast<std::size_t>(mDim.z());
  forEachSlab([&](int x) {
    const std::size_t begin = static_cast<std::size_t>(x) * slabSize;
    double sumSq = 0.0;
    float maxChange = 0.0f;
    for (std::size_t i = begin; i < begin + slabSize; ++i) {
      const float change = fdt * mRates[i];
      mValues[i] += change;
      sumSq += static_cast<double>(change) * change;
      maxChange = std::max(maxChange, std::fabs(change));
    }
    slabSumSq[static_cast<std::size_t>(x)] = sumSq;
    slabMaxChange[static_cast<std::size_t>(x)] = maxChange;
  });

  StepResult result;
  result.dt = dt;
  result.maxSpeed = maxSpeed;
  double sumSq = 0.0;
  for (int x = 0; x < nx; ++x) {
    sumSq += slabSumSq[static_cast<std::size_t>(x)];
    result.maxChange = std::max(result.maxChange, static_cast<double>(slabMaxChange[static_cast<std::size_t>(x)]));
  }
  result.rmsChange = std::sqrt(sumSq / static_cast<double>(mValues.size()));
  result.rmsChangeNotAtRest = result.rmsChange;  // every point is asked
  const float half = static_cast<float>(0.5 * mDx);
  result.activeSetVoxels = static_cast<std::size_t>(
      std::count_if(mValues.begin(), mValues.end(), [half](float v) { return std::fabs(v) <= half; }));
  return result;
}

}  // namespace levelfuse
