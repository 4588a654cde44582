// levelfuse: the time-step rule (section 4.1).

#include <levelfuse/levelset/TimeStep.h>

#include <algorithm>
#include <cmath>

namespace levelfuse {

double stableTimeStep(const TimeStepLimits& limits, double dx, double maxSpeed, double curvatureWeight,
                      double stiffness, double maxDt) {
  double dt = maxDt;
  // Eqs. 31-32: the fastest front over the points may move maxStepChange voxels.
  if (maxSpeed > 0.0) dt = std::min(dt, limits.maxStepChange * dx / maxSpeed);
  // Stability of the explicit curvature term (Eq. 26) and of a stiff force, combined as rates.
  const double curvatureDt = limits.curvatureStepLimit * dx * dx / curvatureWeight;
  const double stiffnessDt = limits.stiffnessStepLimit / stiffness;
  if (curvatureWeight > 0.0 && stiffness > 0.0) dt = std::min(dt, 1.0 / (1.0 / curvatureDt + 1.0 / stiffnessDt));
  else if (curvatureWeight > 0.0) dt = std::min(dt, curvatureDt);
  else if (stiffness > 0.0) dt = std::min(dt, stiffnessDt);
  if (!std::isfinite(dt) || dt < 0.0) dt = 0.0;
  return dt;
}

}  // namespace levelfuse
