// levelfuse: SparseField::step for the MAP evolution's speed.

#include <levelfuse/levelset/SparseFieldStep.h>
#include <levelfuse/recon/DataSpeed.h>

namespace levelfuse {

template StepResult SparseField::step<DataSpeed<DataTermGrids>>(const DataSpeed<DataTermGrids>&, double);
template StepResult SparseField::step<DataSpeed<ForceField>>(const DataSpeed<ForceField>&, double);

}  // namespace levelfuse
