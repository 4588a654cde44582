// Uses the installed levelfuse through its umbrella header: a sphere
// shrinking under curvature flow.
#include <levelfuse/levelfuse.h>

#include <openvdb/tools/LevelSetSphere.h>

#include <iostream>

int main() {
  openvdb::initialize();
  auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(0.0f), 1.0f);
  levelfuse::SparseField field = levelfuse::SparseField::fromLevelSet(*sphere);
  for (int i = 0; i < 10; ++i) field.step(levelfuse::MeanCurvatureFlow{1.0});
  const auto out = field.toLevelSet();
  std::cout << "levelfuse " << levelfuse::version() << ": " << out->activeVoxelCount() << " voxels\n";
  return out->activeVoxelCount() > 0 ? 0 : 1;
}
