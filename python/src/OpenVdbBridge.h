// Grids handed to and from Debian's pyopenvdb (Boost.Python bindings of the same libopenvdb) in
// memory: the grid object itself is shared, so neither its tree nor its values are copied.
#pragma once

#include <pybind11/pybind11.h>

#include <openvdb/openvdb.h>

namespace d2vdb::python {

namespace py = pybind11;

/// The pyopenvdb grid object (FloatGrid, Vec3SGrid, Int32Grid, ...) that holds `grid` itself:
/// changes through either side are seen by both. Imports pyopenvdb; throws InputError when it is
/// not installed or does not bind the grid's type.
py::object toPyopenvdb(const openvdb::GridBase::Ptr& grid);

/// The grid a pyopenvdb grid object holds (shared, not copied), or null when `object` is not one
/// of pyopenvdb's grids of the type T.
template <typename GridType>
typename GridType::Ptr fromPyopenvdb(const py::handle& object);

extern template openvdb::FloatGrid::Ptr fromPyopenvdb<openvdb::FloatGrid>(const py::handle&);

}  // namespace d2vdb::python
