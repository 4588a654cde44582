// levelfuse: SparseField::step and SlabField::computeRates for the speeds the library ships.

#include <levelfuse/levelset/SlabFieldStep.h>
#include <levelfuse/levelset/SparseFieldStep.h>

namespace levelfuse {

template StepResult SparseField::step<MeanCurvatureFlow>(const MeanCurvatureFlow&, double);
template StepResult SparseField::step<ConstantSpeed>(const ConstantSpeed&, double);
template StepResult SparseField::step<ExternalForceSpeed>(const ExternalForceSpeed&, double);

template double SlabField::computeRates<MeanCurvatureFlow>(const MeanCurvatureFlow&);
template double SlabField::computeRates<ConstantSpeed>(const ConstantSpeed&);
template double SlabField::computeRates<ExternalForceSpeed>(const ExternalForceSpeed&);

}  // namespace levelfuse
