// ITK's sparse field as a benchmark peer.

#include "peers/ItkSparseField.h"

#include <itkImage.h>
#include <itkImageRegionIteratorWithIndex.h>
#include <itkLevelSetFunction.h>
#include <itkMultiThreaderBase.h>
#include <itkParallelSparseFieldLevelSetImageFilter.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

namespace levelfuse::peers {
namespace {

using ImageType = itk::Image<float, 3>;
using FunctionType = itk::LevelSetFunction<ImageType>;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The filter with instrumentation only: the time step ITK resolves each
/// iteration, a time stamp per iteration, and its layer sizes.
class InstrumentedFilter : public itk::ParallelSparseFieldLevelSetImageFilter<ImageType, ImageType> {
 public:
  ITK_DISALLOW_COPY_AND_MOVE(InstrumentedFilter);
  using Self = InstrumentedFilter;
  using Superclass = itk::ParallelSparseFieldLevelSetImageFilter<ImageType, ImageType>;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);
  itkTypeMacro(InstrumentedFilter, ParallelSparseFieldLevelSetImageFilter);

  double simulatedTime() const { return mSimulatedTime; }
  std::vector<double>& stamps() { return mStamps; }
  std::size_t layerSize(std::size_t layer) const {
    std::size_t n = 0;
    if (m_Data == nullptr) return 0;
    for (itk::ThreadIdType t = 0; t < m_NumOfThreads; ++t)
      if (layer < m_Data[t].m_Layers.size()) n += m_Data[t].m_Layers[layer]->Size();
    return n;
  }
  std::size_t layerCount() const { return m_Data ? m_Data[0].m_Layers.size() : 0; }
  const ImageType* levelSet() const { return m_OutputImage.GetPointer(); }

 protected:
  InstrumentedFilter() = default;
  ~InstrumentedFilter() override = default;
  void ThreadedApplyUpdate(const TimeStepType& dt, itk::ThreadIdType threadId) override {
    if (threadId == 0) {
      mSimulatedTime += dt;
      mStamps.push_back(now());
    }
    Superclass::ThreadedApplyUpdate(dt, threadId);
  }

 private:
  double mSimulatedTime = 0.0;
  std::vector<double> mStamps;
};

}  // namespace

void itkConfigureThreading(int threads) {
  setenv("ITK_GLOBAL_DEFAULT_THREADER", "Platform", 0);
  itk::MultiThreaderBase::SetGlobalDefaultThreader(itk::MultiThreaderBase::ThreaderEnum::Platform);
  itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(static_cast<itk::ThreadIdType>(threads));
}

struct ItkSparseField::Impl {
  int size = 0;
  double centre = 0.0;
  ImageType::Pointer input;
  FunctionType::Pointer function;
  InstrumentedFilter::Pointer filter;
  bool initialised = false;
  double secondsPerIteration = 0.0;
};

ItkSparseField::ItkSparseField(int radius, int threads, int layers) : mImpl(std::make_unique<Impl>()) {
  Impl& m = *mImpl;
  m.size = 2 * radius + 21;
  m.centre = radius + 10;
  m.input = ImageType::New();
  ImageType::SizeType size;
  size.Fill(static_cast<itk::SizeValueType>(m.size));
  m.input->SetRegions(ImageType::RegionType(size));
  m.input->Allocate();
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(m.input, m.input->GetLargestPossibleRegion()); !it.IsAtEnd();
       ++it) {
    const auto idx = it.GetIndex();
    const double x = idx[0] - m.centre, y = idx[1] - m.centre, z = idx[2] - m.centre;
    it.Set(static_cast<float>(std::sqrt(x * x + y * y + z * z) - radius));
  }

  m.function = FunctionType::New();
  m.function->SetCurvatureWeight(1.0);
  m.function->SetPropagationWeight(0.0);
  m.function->SetAdvectionWeight(0.0);
  m.function->SetLaplacianSmoothingWeight(0.0);
  FunctionType::RadiusType r;
  r.Fill(1);
  m.function->Initialize(r);

  m.filter = InstrumentedFilter::New();
  m.filter->SetInput(m.input);
  m.filter->SetDifferenceFunction(m.function);
  m.filter->SetNumberOfLayers(static_cast<InstrumentedFilter::StatusType>(layers));
  m.filter->SetIsoSurfaceValue(0.0f);
  m.filter->SetMaximumRMSError(0.0);
  m.filter->ManualReinitializationOn();       // keep the sparse field between Update() calls
  m.filter->ReleaseDataBeforeUpdateFlagOff();
  m.filter->GetMultiThreader()->SetMaximumNumberOfThreads(static_cast<itk::ThreadIdType>(threads));
  m.filter->GetMultiThreader()->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(threads));
  m.filter->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(threads));
}

ItkSparseField::~ItkSparseField() = default;

void ItkSparseField::step(int k) {
  Impl& m = *mImpl;
  m.filter->stamps().clear();
  const auto done = m.initialised ? m.filter->GetElapsedIterations() : 0;
  m.filter->SetNumberOfIterations(static_cast<itk::IdentifierType>(done + k));
  m.filter->Update();
  m.initialised = true;
  const auto& s = m.filter->stamps();
  m.secondsPerIteration = s.size() >= 2 ? (s.back() - s.front()) / static_cast<double>(s.size() - 1) : 0.0;
}

double ItkSparseField::lastStepSecondsPerIteration() const { return mImpl->secondsPerIteration; }

double ItkSparseField::meanRadius() const {
  const Impl& m = *mImpl;
  const ImageType* image = m.initialised ? m.filter->levelSet() : m.input.GetPointer();
  const float* v = image->GetBufferPointer();
  const std::size_t n = static_cast<std::size_t>(m.size);
  double sum = 0.0;
  std::size_t count = 0;
  const std::size_t stride[3] = {1, n, n * n};
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t at = i + n * (j + n * k);
        const std::size_t index[3] = {i, j, k};
        for (int axis = 0; axis < 3; ++axis) {
          if (index[axis] + 1 >= n) continue;
          const float a = v[at], b = v[at + stride[axis]];
          if ((a < 0.0f) == (b < 0.0f)) continue;
          double p[3] = {double(i) - m.centre, double(j) - m.centre, double(k) - m.centre};
          p[axis] += double(a) / (double(a) - double(b));
          sum += std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
          ++count;
        }
      }
  return count ? sum / double(count) : 0.0;
}

double ItkSparseField::simulatedTime() const { return mImpl->filter->simulatedTime(); }
std::size_t ItkSparseField::activeSetVoxels() const { return mImpl->filter->layerSize(0); }
std::size_t ItkSparseField::layerNodes() const {
  std::size_t n = 0;
  for (std::size_t l = 0; l < mImpl->filter->layerCount(); ++l) n += mImpl->filter->layerSize(l);
  return n;
}
std::size_t ItkSparseField::imageBytes() const {
  const std::size_t voxels = std::size_t(mImpl->size) * mImpl->size * mImpl->size;
  // Input and output float images and the signed-char status image.
  return voxels * (2 * sizeof(float) + sizeof(signed char));
}

}  // namespace levelfuse::peers
