// levelfuse: SparseField::step for the MAP evolution's speed.

#include <levelfuse/levelset/SparseFieldStep.h>
#include <levelfuse/recon/DataSpeed.h>

namespace levelfuse {

template StepResult SparseField::step<DataSpeed>(const DataSpeed&, double);

}  // namespace levelfuse
