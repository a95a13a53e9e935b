#include "OpenVdbBridge.h"

// Boost.Python only here: pybind11 and Boost.Python share the interpreter, not their headers.
#include <boost/python.hpp>

#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::python {

namespace bp = boost::python;

namespace {

// pyopenvdb registers its grid converters with Boost.Python when it is imported.
void importPyopenvdb() {
  try {
    py::module_::import("pyopenvdb");
  } catch (const py::error_already_set& error) {
    throw InputError(
        std::string("pyopenvdb could not be imported (Debian package python3-openvdb): ") +
        error.what());
  }
}

template <typename GridType>
bool convertible(const openvdb::GridBase::Ptr& grid, py::object& result) {
  const typename GridType::Ptr typed = openvdb::gridPtrCast<GridType>(grid);
  if (!typed) return false;
  try {
    const bp::object object(typed);
    result = py::reinterpret_borrow<py::object>(object.ptr());
  } catch (const bp::error_already_set&) {
    PyErr_Clear();
    throw InputError("pyopenvdb does not bind grids of type " + grid->type());
  }
  return true;
}

}  // namespace

py::object toPyopenvdb(const openvdb::GridBase::Ptr& grid) {
  if (!grid) throw InputError("no grid to hand to pyopenvdb");
  importPyopenvdb();
  py::object result;
  if (convertible<openvdb::FloatGrid>(grid, result) ||
      convertible<openvdb::DoubleGrid>(grid, result) ||
      convertible<openvdb::Int32Grid>(grid, result) ||
      convertible<openvdb::Int64Grid>(grid, result) ||
      convertible<openvdb::BoolGrid>(grid, result) ||
      convertible<openvdb::Vec3SGrid>(grid, result) ||
      convertible<openvdb::Vec3DGrid>(grid, result) ||
      convertible<openvdb::Vec3IGrid>(grid, result)) {
    return result;
  }
  throw InputError("pyopenvdb does not bind grids of type " + grid->type());
}

template <typename GridType>
typename GridType::Ptr fromPyopenvdb(const py::handle& object) {
  importPyopenvdb();
  const bp::object wrapped{bp::handle<>(bp::borrowed(object.ptr()))};
  bp::extract<typename GridType::Ptr> grid(wrapped);
  if (!grid.check()) return nullptr;
  return grid();
}

template openvdb::FloatGrid::Ptr fromPyopenvdb<openvdb::FloatGrid>(const py::handle&);

}  // namespace d2vdb::python
