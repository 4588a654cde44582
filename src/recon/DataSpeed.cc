// levelfuse: SparseField::step and SlabField::computeRates for the MAP evolution's speed.

#include <levelfuse/levelset/SlabFieldStep.h>
#include <levelfuse/levelset/SparseFieldStep.h>
#include <levelfuse/recon/DataSpeed.h>

namespace levelfuse {

template StepResult SparseField::step<DataSpeed<DataTermGrids>>(const DataSpeed<DataTermGrids>&, double);
template StepResult SparseField::step<DataSpeed<ForceField>>(const DataSpeed<ForceField>&, double);
template double SlabField::computeRates<DataSpeed<DataTermGrids>>(const DataSpeed<DataTermGrids>&);
template double SlabField::computeRates<DataSpeed<ForceField>>(const DataSpeed<ForceField>&);

}  // namespace levelfuse
