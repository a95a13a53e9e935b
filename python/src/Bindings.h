// The objects of the d2vdb Python module and the functions that bind each part of the engine.
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // in every file: type casters must agree across the module
#include <pybind11/stl/filesystem.h>

#include <openvdb/openvdb.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/io/InputFile.h"

namespace d2vdb::python {

namespace py = pybind11;

/// d2vdb.LevelSet: a narrow-band distance grid (signed level set or unsigned distance), shared
/// with whoever else holds it (pyopenvdb included), and how it was made.
struct LevelSet {
  openvdb::FloatGrid::Ptr grid;
  double halfWidth = 0;  ///< voxels, as built; 0 when unknown (loaded, from pyopenvdb)
  std::optional<MeshReport> meshReport;  ///< from_mesh(): validateMesh() of the input
  std::optional<SignReport> signs;       ///< from_mesh(): how inside/outside was decided
  std::vector<std::string> warnings;
};

/// d2vdb.Field: an approximant field (immutable once built, so shared freely).
struct Field {
  std::shared_ptr<const ApproximantField> field;
  InputKind of = InputKind::Field;  ///< what the field is of
  std::vector<std::string> warnings;
  std::optional<SignReport> signs;
};

/// d2vdb.PointSet: points in file order (world units).
struct PointSet {
  std::vector<Eigen::Vector3d> points;
};

/// d2vdb.SupportFunction: a support-function document as its .json file holds it.
struct SupportFunctionObject {
  SupportFunctionDocument document;
};

/// A Mesh, PointSet, Curve or Surface, or anything numpy reads as (N, 3) points, as loadInput()
/// would return it from a file (`label` stands for the file's path in labels and messages).
/// Throws InputError for points that are not (N, 3) and finite.
LoadedInput inputOf(const py::handle& target, const std::filesystem::path& label);

/// Raises FileNotFoundError (a Python exception) when `path` does not exist.
void requireExistingFile(const std::filesystem::path& path);

void bindMesh(py::module_& module);
void bindLevelSet(py::module_& module);
void bindField(py::module_& module);
void bindSplines(py::module_& module);
void bindSupport(py::module_& module);
void bindLoad(py::module_& module);
void bindFit(py::module_& module);
void bindMeasure(py::module_& module);
void bindSmooth(py::module_& module);
void bindBenchmarkHooks(py::module_& module);

}  // namespace d2vdb::python
