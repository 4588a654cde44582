// levelfuse Python module: levelfuse.SparseField, the sparse-field level-set
// engine alone, moved by its built-in speeds or by a force that Python
// computes for all active points at once.

#include "Arrays.h"
#include "Bindings.h"
#include "Cancellation.h"
#include "PyOpenVdb.h"

#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SparseFieldStep.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <openvdb/tree/LeafManager.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

namespace levelfuse {

/// A force tabulated at the active points (by index coordinate), plus the
/// surface-area prior: the speed of a force Python computed for the step.
struct TabulatedForceSpeed {
  const openvdb::FloatTree* forces = nullptr;
  double beta = 0.0;

  float operator()(const ActivePoint& p) const { return forceRate(p.stencil, forces->getValue(p.ijk), beta); }
  double curvatureWeight() const { return beta; }
};

template StepResult SparseField::step<TabulatedForceSpeed>(const TabulatedForceSpeed&, double);

namespace python {
namespace {

/// The active set's points: index coordinates, subcell positions x^ (Eqs.
/// 34-36) and outward normals, as the engine's speeds see them, in the order
/// of the grid's leaves.
struct ActivePoints {
  std::vector<openvdb::Coord> ijk;
  std::vector<openvdb::Vec3d> position, normal;
};

ActivePoints activePointsOf(const SparseField& field) {
  const openvdb::FloatGrid& grid = field.grid();
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(grid.tree());
  std::vector<ActivePoints> perLeaf(leaves.leafCount());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.leafCount()), [&](const auto& range) {
    openvdb::FloatGrid::ConstAccessor values = grid.getConstAccessor();
    const openvdb::math::MapBase& map = *grid.transform().baseMap();  // the transform holds it
    Stencil stencil;
    stencil.h = static_cast<float>(field.voxelSize());
    for (std::size_t n = range.begin(); n != range.end(); ++n) {
      ActivePoints& out = perLeaf[n];
      for (auto it = leaves.leaf(n).cbeginValueOn(); it; ++it) {
        const openvdb::Coord ijk = it.getCoord();
        if (field.layerOf(ijk) != 0) continue;
        for (int s = 0; s < Stencil::kSize; ++s)
          stencil.u[s] = values.getValue(ijk.offsetBy(Stencil::kOffset[s][0], Stencil::kOffset[s][1], Stencil::kOffset[s][2]));
        const ActivePoint p{stencil, ijk, grid.transform(), map};
        out.ijk.push_back(ijk);
        out.position.push_back(p.subcellPosition());
        out.normal.push_back(p.normal());
      }
    }
  });
  ActivePoints all;
  for (ActivePoints& p : perLeaf) {
    all.ijk.insert(all.ijk.end(), p.ijk.begin(), p.ijk.end());
    all.position.insert(all.position.end(), p.position.begin(), p.position.end());
    all.normal.insert(all.normal.end(), p.normal.begin(), p.normal.end());
  }
  return all;
}

/// The Python force's speeds at the active points, tabulated by index coordinate.
openvdb::FloatTree::Ptr tabulatedForce(const SparseField& field, const py::function& force) {
  ActivePoints points;
  {
    py::gil_scoped_release released;
    points = activePointsOf(field);
  }
  const py::object answer = force(numpyPoints(points.position), numpyPoints(points.normal));
  py::array_t<double, py::array::c_style | py::array::forcecast> speeds;
  try {
    speeds = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(answer);
  } catch (const py::error_already_set&) {
  }
  if (!speeds || speeds.ndim() != 1 || static_cast<std::size_t>(speeds.shape(0)) != points.ijk.size())
    throw py::value_error("force(x, n) must return an array of " + std::to_string(points.ijk.size()) +
                          " speeds, one per active point");
  auto forces = std::make_shared<openvdb::FloatTree>(0.0f);
  openvdb::tree::ValueAccessor<openvdb::FloatTree> acc(*forces);
  const double* s = speeds.data();
  for (std::size_t i = 0; i < points.ijk.size(); ++i) {
    if (!std::isfinite(s[i])) throw py::value_error("force(x, n) returned a speed that is not finite");
    acc.setValueOn(points.ijk[i], static_cast<float>(s[i]));
  }
  return forces;
}

py::dict stepReport(const StepResult& r) {
  py::dict d;
  d["dt"] = r.dt;
  d["max_speed"] = r.maxSpeed;
  d["max_change"] = r.maxChange;
  d["rms_change"] = r.rmsChange;
  d["active_set_voxels"] = r.activeSetVoxels;
  d["moved_out"] = r.movedOut;
  d["moved_in"] = r.movedIn;
  d["conflicts"] = r.conflicts;
  return d;
}

/// One step under `force` (None, a number: a constant outward speed, or a
/// callable force(x, n) -> speeds) and the prior of weight `beta`.
StepResult stepOnce(SparseField& field, const py::object& force, double beta, double maxDt) {
  if (!(beta >= 0.0) || !std::isfinite(beta)) throw py::value_error("beta must be a finite number, 0 or more");
  if (force.is_none()) {
    if (beta == 0.0) throw py::value_error("nothing moves the surface: give a force, beta > 0, or both");
    py::gil_scoped_release released;
    return field.step(MeanCurvatureFlow{beta}, maxDt);
  }
  if (py::isinstance<py::function>(force)) {
    const openvdb::FloatTree::Ptr forces = tabulatedForce(field, py::reinterpret_borrow<py::function>(force));
    py::gil_scoped_release released;
    return field.step(TabulatedForceSpeed{forces.get(), beta}, maxDt);
  }
  const double speed = numberFrom(force, "force", false);
  py::gil_scoped_release released;
  return field.step(ConstantSpeed{ConstantForce{speed}, beta}, maxDt);
}

SparseFieldOptions engineOptions(int layers, double maxStepChange, std::size_t grainSize) {
  SparseFieldOptions o;
  o.layers = layers;
  o.maxStepChange = maxStepChange;
  o.grainSize = grainSize;
  return o;
}

SparseField fieldOfLevelSet(const py::handle& levelSet, int layers, double maxStepChange, std::size_t grainSize) {
  const openvdb::FloatGrid::Ptr grid = gridFrom(levelSet, "level_set");
  py::gil_scoped_release released;
  return SparseField::fromLevelSet(*grid, engineOptions(layers, maxStepChange, grainSize));
}

SparseField fieldOfMask(const py::handle& mask, double voxelSize, const py::handle& origin, int layers,
                        double maxStepChange, std::size_t grainSize) {
  const py::array a = requireArray(mask, "mask", 3);
  if (!holds<bool>(a)) throw wrongDtype("mask", a, "bool");
  numberFrom(py::float_(voxelSize), "voxel_size", true);
  const openvdb::Vec3d o = origin.is_none() ? openvdb::Vec3d(0.0) : vec3From(origin, "origin");
  auto inside = openvdb::MaskGrid::create();
  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  transform->postTranslate(o);
  inside->setTransform(transform);
  const bool* v = static_cast<const bool*>(a.data());
  const py::ssize_t nj = a.shape(1), nk = a.shape(2);
  py::gil_scoped_release released;
  openvdb::MaskGrid::Accessor acc = inside->getAccessor();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (py::ssize_t j = 0; j < nj; ++j)
      for (py::ssize_t k = 0; k < nk; ++k)
        if (v[(i * nj + j) * nk + k])
          acc.setValueOn(openvdb::Coord(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)));
  return SparseField::fromMask(*inside, engineOptions(layers, maxStepChange, grainSize));
}

py::dict stepOf(SparseField& f, const py::object& force, double beta, double maxDt) {
  return stepReport(stepOnce(f, force, beta, maxDt));
}

/// Steps until `duration` has passed (or Ctrl-C); the number of steps.
std::size_t advanceBy(SparseField& f, double duration, const py::object& force, double beta) {
  if (!(duration >= 0.0) || !std::isfinite(duration)) throw py::value_error("duration must be a finite time, 0 or more");
  Cancellation cancellation;
  std::size_t steps = 0;
  for (double t = 0.0; t < duration; ++steps) {
    const StepResult r = stepOnce(f, force, beta, duration - t);
    if (r.dt <= 0.0) break;
    t += r.dt;
    if (cancellation.stopped()) break;
  }
  cancellation.raiseIfSignalled();
  return steps;
}

py::tuple activePointArrays(const SparseField& f) {
  ActivePoints points;
  {
    py::gil_scoped_release released;
    points = activePointsOf(f);
  }
  py::array_t<std::int32_t> ijk({static_cast<py::ssize_t>(points.ijk.size()), py::ssize_t{3}});
  std::int32_t* c = ijk.mutable_data();
  for (const openvdb::Coord& p : points.ijk)
    for (int a = 0; a < 3; ++a) *c++ = p[a];
  return py::make_tuple(ijk, numpyPoints(points.position), numpyPoints(points.normal));
}

py::object levelSetForPython(const SparseField& f, double halfWidth, const std::string& name) {
  openvdb::FloatGrid::Ptr grid;
  {
    py::gil_scoped_release released;
    grid = f.toLevelSet(halfWidth, name);
  }
  return gridForPython(grid);
}

py::dict statsOf(const SparseField& f) {
  const SparseFieldStats s = f.stats();
  py::dict d;
  d["active_set_voxels"] = s.activeSetVoxels;
  d["band_voxels"] = s.bandVoxels;
  d["leaf_nodes"] = s.leafNodes;
  d["memory_bytes"] = s.memoryBytes;
  return d;
}

/// SparseField's constructors: from a level set and from a mask.
void defineSparseFieldConstructors(py::class_<SparseField>& field) {
  field
      .def(py::init(&fieldOfLevelSet), py::arg("level_set"), py::kw_only(), py::arg("layers") = 2,
           py::arg("max_step_change") = 0.45, py::arg("grain_size") = 4,
           "From a level set: a levelfuse.Grid or a pyopenvdb.FloatGrid.")
      .def_static("from_mask", &fieldOfMask, py::arg("mask"), py::kw_only(), py::arg("voxel_size") = 1.0,
                  py::arg("origin") = py::none(), py::arg("layers") = 2, py::arg("max_step_change") = 0.45,
                  py::arg("grain_size") = 4,
                  "From a boolean occupancy array (True inside), element [i, j, k] the voxel at index (i, j, k), "
                  "world position origin + voxel_size * (i, j, k): the surface runs halfway between inside and "
                  "outside.");
}

/// SparseField's motion: step and advance.
void defineSparseFieldMotion(py::class_<SparseField>& field) {
  field
      .def("step", &stepOf, py::kw_only(), py::arg("force") = py::none(), py::arg("beta") = 0.0,
           py::arg("max_dt") = std::numeric_limits<double>::infinity(),
           "One time step (at most max_dt) under force (None, an outward speed, or force(x, n) -> speeds) and the "
           "prior of weight beta (world units squared per unit time). Returns what the step did.")
      .def("advance", &advanceBy, py::arg("duration"), py::kw_only(), py::arg("force") = py::none(),
           py::arg("beta") = 0.0,
           "Steps until `duration` has passed; returns the number of steps. Ctrl-C stops between steps "
           "(KeyboardInterrupt).");
}

}  // namespace

void bindEngine(py::module_& m) {
  py::class_<SparseField> field(m, "SparseField", R"doc(The sparse-field level-set engine (section 5 of the paper): an
OpenVDB level set with its active set and layers, moved step by step. Built-in speeds: the surface-area prior
(mean-curvature flow, weight beta) and a constant outward speed; or a force computed in Python, called once
per step with every active point's subcell position x^ (N, 3) and outward normal (N, 3), returning (N,)
outward speeds.)doc");
  defineSparseFieldConstructors(field);
  defineSparseFieldMotion(field);
  field
      .def("active_points", &activePointArrays,
           "(coords, x, normals): the active set's index coordinates (N, 3) int32, subcell positions x^ (N, 3) and "
           "outward normals (N, 3), as a force sees them.")
      .def("level_set", &levelSetForPython, py::kw_only(), py::arg("half_width") = 3.0, py::arg("name") = "surface",
           "A standard OpenVDB level set of the surface (a pyopenvdb.FloatGrid where installed, else a "
           "levelfuse.Grid).")
      .def(
          "grid", [](const SparseField& f, double halfWidth, const std::string& name) { return f.toLevelSet(halfWidth, name); },
          py::kw_only(), py::arg("half_width") = 3.0, py::arg("name") = "surface",
          "The same level set as a levelfuse.Grid.")
      .def("layer_of", [](const SparseField& f, int i, int j, int k) { return f.layerOf(openvdb::Coord(i, j, k)); },
           py::arg("i"), py::arg("j"), py::arg("k"), "0 for the active set, +-n for layer n, +-(layers+1) beyond.")
      .def_property_readonly("voxel_size", &SparseField::voxelSize)
      .def_property_readonly("layers", &SparseField::layers)
      .def_property_readonly("stats", &statsOf);
}

}  // namespace python
}  // namespace levelfuse
