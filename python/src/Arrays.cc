#include "Arrays.h"

#include <cmath>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb::python {

namespace {

// The array as a C-contiguous array of T (numpy's cast; a copy only when it must convert).
template <typename T>
py::array_t<T, py::array::c_style | py::array::forcecast> asArray(const py::handle& object,
                                                                  const std::string& what) {
  try {
    return py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(object)
        .template cast<py::array_t<T, py::array::c_style | py::array::forcecast>>();
  } catch (const py::error_already_set&) {
    throw InputError(what + " must be an array of numbers (numpy could not convert a " +
                     std::string(py::str(py::type::of(object).attr("__name__"))) + ")");
  }
}

std::string shapeText(const py::array& array) {
  std::ostringstream text;
  text << "(";
  for (py::ssize_t axis = 0; axis < array.ndim(); ++axis) {
    text << (axis ? ", " : "") << array.shape(axis);
  }
  text << (array.ndim() == 1 ? ",)" : ")");
  return text.str();
}

template <typename Array>
void requireRowsOfThree(const Array& array, const std::string& what, const char* rows = "N") {
  if (array.ndim() != 2 || array.shape(1) != 3) {
    throw InputError(what + " must have shape (" + rows + ", 3); it has shape " + shapeText(array));
  }
}

template <typename Vector, typename Scalar>
std::vector<Vector> finiteRows(const py::handle& object, const std::string& what) {
  if (object.is_none()) throw InputError(what + " must be an (N, 3) array; got None");
  const auto array = asArray<double>(object, what);
  requireRowsOfThree(array, what);
  const auto rows = static_cast<std::size_t>(array.shape(0));
  const double* values = array.data();
  std::vector<Vector> result(rows);
  for (std::size_t row = 0; row < rows; ++row) {
    for (int axis = 0; axis < 3; ++axis) {
      const double value = values[3 * row + static_cast<std::size_t>(axis)];
      if (!std::isfinite(value)) {
        throw InputError(what + "[" + std::to_string(row) + ", " + std::to_string(axis) + "] is " +
                         formatNumber(value, 6) + "; coordinates must be finite");
      }
      result[row][axis] = static_cast<Scalar>(value);
    }
  }
  return result;
}

}  // namespace

std::vector<Eigen::Vector3d> pointsFromArray(const py::handle& array, const std::string& what) {
  return finiteRows<Eigen::Vector3d, double>(array, what);
}

std::vector<Eigen::Vector3f> positionsFromArray(const py::handle& array, const std::string& what) {
  return finiteRows<Eigen::Vector3f, float>(array, what);
}

std::vector<TriangleMesh::Triangle> trianglesFromArray(const py::handle& object,
                                                       std::size_t vertexCount,
                                                       const std::string& what) {
  if (object.is_none()) throw InputError(what + " must be an (M, 3) array; got None");
  const py::array raw = py::array::ensure(object);
  if (!raw) throw InputError(what + " must be an (M, 3) array of vertex indices");
  const char kind = raw.dtype().kind();
  if (raw.size() > 0 && kind != 'i' && kind != 'u') {
    throw InputError(what + " must hold integer vertex indices; its dtype is " +
                     std::string(py::str(raw.dtype())));
  }
  const auto array = asArray<std::int64_t>(raw, what);
  requireRowsOfThree(array, what, "M");
  const auto rows = static_cast<std::size_t>(array.shape(0));
  const std::int64_t* values = array.data();
  std::vector<TriangleMesh::Triangle> triangles(rows);
  for (std::size_t row = 0; row < rows; ++row) {
    for (std::size_t corner = 0; corner < 3; ++corner) {
      const std::int64_t index = values[3 * row + corner];
      if (index < 0 || static_cast<std::uint64_t>(index) >= vertexCount) {
        throw InputError(what + "[" + std::to_string(row) + ", " + std::to_string(corner) +
                         "] is " + std::to_string(index) + "; vertex indices must lie in [0, " +
                         std::to_string(vertexCount) + ")");
      }
      triangles[row][corner] = static_cast<TriangleMesh::Index>(index);
    }
  }
  return triangles;
}

Eigen::Vector3d vector3FromObject(const py::handle& value, const std::string& what) {
  const auto array = asArray<double>(value, what);
  if (array.ndim() != 1 || array.shape(0) != 3) {
    throw InputError(what + " must be three numbers; it has shape " + shapeText(array));
  }
  const Eigen::Vector3d result(array.data()[0], array.data()[1], array.data()[2]);
  if (!result.allFinite()) throw InputError(what + " must be finite");
  return result;
}

py::array_t<double> arrayOfPoints(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> values(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis)
      values[3 * i + static_cast<std::size_t>(axis)] = points[i][axis];
  }
  return arrayOwning(std::move(values), {static_cast<py::ssize_t>(points.size()), 3});
}

py::tuple boxTuple(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  return py::make_tuple(py::make_tuple(min.x(), min.y(), min.z()),
                        py::make_tuple(max.x(), max.y(), max.z()));
}

}  // namespace d2vdb::python
