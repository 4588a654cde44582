// levelfuse: SparseField::step for the speeds the library ships.

#include <levelfuse/levelset/SparseFieldStep.h>

namespace levelfuse {

template StepResult SparseField::step<MeanCurvatureFlow>(const MeanCurvatureFlow&, double);
template StepResult SparseField::step<ConstantSpeed>(const ConstantSpeed&, double);
template StepResult SparseField::step<ExternalForceSpeed>(const ExternalForceSpeed&, double);

}  // namespace levelfuse
