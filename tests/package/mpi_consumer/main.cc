// Uses the installed levelfuse's MPI layer: a sphere under curvature flow,
// shared by the ranks of the job (one rank when run without mpirun), gives
// the level set one process gives.
#include <levelfuse/levelfuse.h>
#include <levelfuse/mpi/RankTeam.h>

#include <openvdb/tools/LevelSetSphere.h>

#include <mpi.h>

#include <iostream>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  openvdb::initialize();
  const levelfuse::mpi::RankTeam team;
  auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(0.0f), 1.0f);
  levelfuse::SlabField slab = levelfuse::SlabField::fromLevelSet(
      *sphere, levelfuse::balancedSlabs(levelfuse::leafColumns(sphere->tree()), team.size())
                   .at(static_cast<std::size_t>(team.rank())));
  for (int i = 0; i < 10; ++i) levelfuse::stepSlab(slab, levelfuse::MeanCurvatureFlow{1.0}, team);
  const std::uint64_t voxels = team.total(slab.stats().activeSetVoxels);
  if (team.rank() == 0)
    std::cout << "levelfuse " << levelfuse::version() << " on " << team.size() << (team.size() == 1 ? " rank: " : " ranks: ")
              << voxels << " voxels in the active set\n";
  MPI_Finalize();
  return voxels > 0 ? 0 : 1;
}
