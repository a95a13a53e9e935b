// numpy arrays in and out of the d2vdb module: any array-like numpy can cast is accepted (C or
// Fortran order, strided, float32 or float64, integer indices of any width); shapes, finiteness
// and index ranges are checked with an InputError naming the first bad element.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::python {

namespace py = pybind11;

/// An (N, 3) array of finite coordinates as doubles (one converted copy, as numpy casts). Throws
/// InputError for another shape or a NaN/infinite coordinate, naming `what` and the element
/// ("points[12, 1] is nan").
std::vector<Eigen::Vector3d> pointsFromArray(const py::handle& array, const std::string& what);

/// As pointsFromArray(), as floats (the precision of TriangleMesh positions).
std::vector<Eigen::Vector3f> positionsFromArray(const py::handle& array, const std::string& what);

/// An (M, 3) array of integer vertex indices in [0, vertexCount). Throws InputError for another
/// shape, a non-integer dtype, and a negative or out-of-range index, naming the element.
std::vector<TriangleMesh::Triangle> trianglesFromArray(const py::handle& array,
                                                       std::size_t vertexCount,
                                                       const std::string& what);

/// A 3-vector from any sequence of three finite numbers (InputError otherwise).
Eigen::Vector3d vector3FromObject(const py::handle& value, const std::string& what);

/// A new numpy array of `shape` that owns `values` (moved in, not copied).
template <typename T>
py::array_t<T> arrayOwning(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(values));
  const py::capsule release(owned,
                            [](void* pointer) { delete static_cast<std::vector<T>*>(pointer); });
  return py::array_t<T>(shape, owned->data(), release);
}

/// A read-only (rows, 3) view of `rows` contiguous triples of T at `data`, kept alive by `owner`.
template <typename T>
py::array_t<T> readOnlyRows(const T* data, std::size_t rows, const py::handle& owner) {
  py::array_t<T> view(
      {static_cast<py::ssize_t>(rows), py::ssize_t{3}},
      {static_cast<py::ssize_t>(3 * sizeof(T)), static_cast<py::ssize_t>(sizeof(T))}, data, owner);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

/// (N, 3) float64 array of the points (one copy).
py::array_t<double> arrayOfPoints(const std::vector<Eigen::Vector3d>& points);

/// (min, max) of a box as a tuple of two 3-tuples.
py::tuple boxTuple(const Eigen::Vector3d& min, const Eigen::Vector3d& max);

}  // namespace d2vdb::python
