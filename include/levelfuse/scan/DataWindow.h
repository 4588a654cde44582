// levelfuse: the window w(D) that limits a reading's reach along its line of
// sight (paper Eqs. 8-9).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace levelfuse {

enum class WindowKind {
  kGaussian,  ///< exp(-D^2 / (2 eps^2)), as in the paper's results, cut at `reach` eps
  kBinary,    ///< 1 for -eps <= D < eps: a reading reaches eps in front of and behind itself
};

/// The names of the window kinds, in the order of WindowKind: "gaussian", "binary".
const std::vector<std::string>& windowKindNames();
/// A window kind's name (windowKindNames).
const std::string& windowKindName(WindowKind kind);
/// The window kind of a name of windowKindNames. Throws std::invalid_argument
/// listing those names for any other ("window must be 'gaussian' or 'binary',
/// not 'box'").
WindowKind windowKindFromName(const std::string& name);

/// w(D) of Eqs. 8-9 for a reading at signed distance D (world units) along
/// its line of sight. The Gaussian is tabulated in (D / eps)^2 up to its cut
/// and interpolated linearly, within 1e-6 of the exponential.
class DataWindow {
 public:
  /// Throws std::invalid_argument unless epsilon and reach are positive and finite.
  DataWindow(WindowKind kind, double epsilon, double reach);

  double operator()(double D) const {
    if (mKind == WindowKind::kBinary) return (D >= -mEpsilon && D < mEpsilon) ? 1.0 : 0.0;
    const double x = D * D * mTableScale;
    if (!(x < static_cast<double>(mGaussian.size() - 1))) return 0.0;
    const std::size_t i = static_cast<std::size_t>(x);
    const double f = x - static_cast<double>(i);
    return mGaussian[i] + f * (mGaussian[i + 1] - mGaussian[i]);
  }
  /// How far from its reading w is non-zero: eps (binary) or reach * eps.
  double reach() const { return mKind == WindowKind::kBinary ? mEpsilon : mReach * mEpsilon; }
  double epsilon() const { return mEpsilon; }
  WindowKind kind() const { return mKind; }

 private:
  WindowKind mKind;
  double mEpsilon, mReach;
  std::vector<double> mGaussian;  ///< exp(-x / 2) at x = (D / eps)^2 = i / (table scale * eps^2)
  double mTableScale = 1.0;       ///< table entries per unit of D^2
};

}  // namespace levelfuse
