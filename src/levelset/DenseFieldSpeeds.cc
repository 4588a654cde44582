// levelfuse: DenseField::step for the speeds the library ships.

#include <levelfuse/levelset/DenseFieldStep.h>

namespace levelfuse {

template StepResult DenseField::step<MeanCurvatureFlow>(const MeanCurvatureFlow&, double);
template StepResult DenseField::step<ConstantSpeed>(const ConstantSpeed&, double);
template StepResult DenseField::step<ExternalForceSpeed>(const ExternalForceSpeed&, double);

}  // namespace levelfuse
