// levelfuse: the window of a reading (Eqs. 8-9).

#include <levelfuse/scan/DataWindow.h>

#include <cmath>
#include <stdexcept>

namespace levelfuse {

const std::vector<std::string>& windowKindNames() {
  static const std::vector<std::string> names{"gaussian", "binary"};
  return names;
}

const std::string& windowKindName(WindowKind kind) { return windowKindNames()[static_cast<std::size_t>(kind)]; }

WindowKind windowKindFromName(const std::string& name) {
  const std::vector<std::string>& names = windowKindNames();
  std::string accepted;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (name == names[k]) return static_cast<WindowKind>(k);
    accepted += (k == 0 ? "'" : k + 1 == names.size() ? " or '" : ", '") + names[k] + "'";
  }
  throw std::invalid_argument("window must be " + accepted + ", not '" + name + "'");
}

DataWindow::DataWindow(WindowKind kind, double epsilon, double reach) : mKind(kind), mEpsilon(epsilon), mReach(reach) {
  if (!(epsilon > 0.0) || !std::isfinite(epsilon))
    throw std::invalid_argument("the window width epsilon must be positive and finite");
  if (!(reach > 0.0) || !std::isfinite(reach)) throw std::invalid_argument("the window reach must be positive and finite");
  // exp(-x / 2) in x = (D / eps)^2 up to reach^2, 4096 entries and a zero beyond.
  const std::size_t entries = 4096;
  const double perUnitX = static_cast<double>(entries - 1) / (reach * reach);
  mTableScale = perUnitX / (epsilon * epsilon);
  mGaussian.resize(entries + 1);
  for (std::size_t i = 0; i < entries; ++i) mGaussian[i] = std::exp(-0.5 * static_cast<double>(i) / perUnitX);
  mGaussian[entries] = 0.0;
}

}  // namespace levelfuse
