// ITK's sparse field as a benchmark peer: mean-curvature flow of a sphere with
// itk::ParallelSparseFieldLevelSetImageFilter. This header includes no ITK or
// OpenVDB header, so the two never meet in one translation unit.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace levelfuse::peers {

/// Selects ITK's Platform threader (5.2's pool threader deadlocks this filter,
/// whose work units wait on one another) with `threads` threads.
void itkConfigureThreading(int threads);

/// Mean-curvature flow of a sphere of `radius` voxels on a dense float image of
/// (2R + 21)^3 voxels holding its exact signed distance (negative inside), with
/// a curvature-only itk::LevelSetFunction (CurvatureWeight 1), so that
/// d phi/dt = kappa |grad phi| with kappa the sum of principal curvatures.
class ItkSparseField {
 public:
  ItkSparseField(int radius, int threads, int layers = 2);
  ~ItkSparseField();
  ItkSparseField(const ItkSparseField&) = delete;
  ItkSparseField& operator=(const ItkSparseField&) = delete;

  /// Runs exactly k more iterations (the first call also initialises the
  /// sparse field). Each call ends with ITK's full-image post-processing pass.
  void step(int k);
  /// Mean wall time of one iteration inside the last step() call, from time
  /// stamps taken as each iteration applies its update: excludes the set-up
  /// and post-processing of the Update() call.
  double lastStepSecondsPerIteration() const;

  /// Mean distance of the zero crossings from the sphere's centre, in voxels.
  double meanRadius() const;
  /// Sum of ITK's time steps so far.
  double simulatedTime() const;
  std::size_t activeSetVoxels() const;
  /// Nodes of all layers, the active one included.
  std::size_t layerNodes() const;
  /// Bytes of the images the filter holds (input, output and status images).
  std::size_t imageBytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> mImpl;
};

}  // namespace levelfuse::peers
