// The extension module d2vdb._d2vdb; python/d2vdb/__init__.py re-exports it as d2vdb.
#include <pybind11/pybind11.h>

#include <openvdb/openvdb.h>

#include <cerrno>

#include "Bindings.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/Version.h"

namespace d2vdb::python {

void requireExistingFile(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::exists(path, error)) return;
  const py::object notFound =
      py::module_::import("builtins")
          .attr("FileNotFoundError")(ENOENT, "No such file or directory", path.string());
  PyErr_SetObject(PyExc_FileNotFoundError, notFound.ptr());
  throw py::error_already_set();
}

}  // namespace d2vdb::python

PYBIND11_MODULE(_d2vdb, module) {
  namespace py = pybind11;
  using namespace d2vdb::python;
  openvdb::initialize();
  module.doc() =
      "d2vdb: narrow-band distance fields that carry local quadratic approximants of the squared "
      "distance, fitting of B-spline curves and surfaces, and meshing of level sets, from numpy "
      "arrays. World units throughout; signed distances are negative inside.";
  module.attr("__version__") = d2vdb::kVersion;
  // Engine failures: InputError (bad input, a ValueError) and RuntimeFailure (a RuntimeError).
  py::register_exception<d2vdb::InputError>(module, "InputError", PyExc_ValueError)
      .attr("__module__") = "d2vdb";
  py::register_exception<d2vdb::RuntimeFailure>(module, "RuntimeFailure", PyExc_RuntimeError)
      .attr("__module__") = "d2vdb";
  bindMesh(module);
  bindLevelSet(module);
  bindField(module);
  bindSplines(module);
  bindSupport(module);
  bindLoad(module);
  bindFit(module);
  bindMeasure(module);
  bindSmooth(module);
  bindBenchmarkHooks(module);
}
