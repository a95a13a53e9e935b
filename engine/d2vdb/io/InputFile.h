// One way in for files: loadInput() reads any input d2vdb works on (meshes, point sets, .vdb level
// sets and approximant fields, B-spline curves and surfaces, polylines, support functions),
// recognising the file by its content and, where the content cannot tell, by its extension.
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/io/GridSelection.h"
#include "d2vdb/io/SupportFunctionJson.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"

// How a file is recognised
// ========================
// By content first, so that a misleading extension does not matter where the format has a
// signature:
//   .vdb   the OpenVDB magic number in the first 8 bytes
//   PLY    "ply" on the first line
//   JSON   a document starting with '{' (after white space); its "type" says what it holds:
//          "bspline_curve", "bspline_surface", "polyline", "support_function", or no "type" and a
//          "polylines" list (`d2vdb slice --polylines` files)
//   STL    "solid" at the start (ASCII; the STL reader also accepts binary files whose 80-byte
//          header starts so), or a size of exactly 84 + 50 n bytes for the n triangles the binary
//          header announces
//   OBJ    the first line that is neither blank nor a '#' comment starts with an OBJ keyword
//          (v, vn, vt, vp, f, l, p, o, g, s, mtllib, usemtl)
//   .xyz   that line starts with a number
// then, when none of these fits (a truncated binary STL, say), by the extension (.vdb, .ply,
// .json, .stl, .obj, .xyz, any letter case). A file that is neither is an InputError naming the
// file and what was expected.
//
// Adding a kind of input: a value in InputKind, its type in LoadedInput::Value (same position),
// its row in the kind table of InputFile.cc (name, files), and its recognition there (a JSON "type"
// or a file format). Every caller then gets it through the same entry point.

namespace d2vdb {

/// What loadInput() returns a file as.
enum class InputKind {
  Mesh,             ///< a triangle mesh: OBJ, STL, or PLY with faces (MeshInput)
  PointSet,         ///< points: .xyz, or the vertices of a PLY (PointSetInput)
  LevelSet,         ///< one scalar grid of a .vdb file, chosen by selectGrid() (LevelSetInput)
  Field,            ///< an approximant field: stored in a .vdb by `d2vdb field`, or computed from a
                    ///< level set .vdb (FieldInput)
  VdbGrids,         ///< every grid of a .vdb file, none chosen (VdbGridsInput)
  Curve,            ///< a B-spline curve .json (BSplineCurve)
  Surface,          ///< a B-spline surface .json (BSplineSurface)
  Polylines,        ///< a polyline .json, or the polylines of a slice file (PolylinesInput)
  SupportFunction,  ///< a support-function .json (SupportFunctionDocument, SupportFunctionJson.h)
};

/// The name reports give a kind: "mesh", "points", "level set", "field", "grids", "curve",
/// "surface", "polyline" or "support function" (the "input_kind" values of the JSON reports).
const char* inputKindName(InputKind kind);

/// A set of InputKinds, written as a list: {InputKind::Curve, InputKind::Polylines}.
class InputKinds {
 public:
  constexpr InputKinds(std::initializer_list<InputKind> kinds) {
    for (const InputKind kind : kinds) bits_ |= bit(kind);
  }
  constexpr bool contains(InputKind kind) const { return (bits_ & bit(kind)) != 0; }
  constexpr bool empty() const { return bits_ == 0; }

 private:
  static constexpr std::uint32_t bit(InputKind kind) {
    return std::uint32_t{1} << static_cast<unsigned>(kind);
  }
  std::uint32_t bits_ = 0;
};

/// A triangle mesh and the format it was read in.
struct MeshInput {
  TriangleMesh mesh;
  MeshFormat format = MeshFormat::Obj;
};

/// A point set, in file order (PLY coordinates pass through the mesh reader's 32-bit floats).
struct PointSetInput {
  std::vector<Eigen::Vector3d> points;
};

/// A .vdb file with the scalar grid a command works on.
struct LevelSetInput {
  std::vector<openvdb::GridBase::Ptr> grids;  ///< every grid of the file, in file order
  openvdb::GridBase::Ptr grid;  ///< selectGrid(grids, ..., LoadOptions::gridName, gridTypes)
  /// `grid` as a FloatGrid; null when it is a DoubleGrid (LoadOptions::gridTypes allowed it).
  openvdb::FloatGrid::Ptr floatGrid() const {
    return openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
  }
};

/// An approximant field.
struct FieldInput {
  ApproximantField field;
  /// True when the file stored the field (its companion grids were read back, bit for bit);
  /// false when it held a level set whose approximants were computed now.
  bool stored = false;
};

/// Every grid of a .vdb file, in file order.
struct VdbGridsInput {
  std::vector<openvdb::GridBase::Ptr> grids;
};

/// The polylines of a polyline file (one) or of a slice file (any number, possibly none);
/// onlyPolyline() (PolylineFile.h) takes the one a command needs.
struct PolylinesInput {
  std::vector<Polyline> polylines;
};

/// How loadInput() reads a file.
struct LoadOptions {
  /// Who needs the file, for messages: "... ; <purpose> must be <the accepted kinds>", e.g.
  /// "the target of 'd2vdb fit-curve'".
  std::string purpose = "the input";
  /// LevelSet (and Field from a level set): the grid to take (empty: selectGrid()'s rule).
  std::string gridName;
  /// LevelSet: the value types the chosen grid may hold (Field always needs float).
  ScalarGridTypes gridTypes = ScalarGridTypes::Float;
  /// Field: how the field is built (domain padding, voxel budget, ...).
  ApproximantFieldOptions field;
  /// Field: progress while the field is read or built (may be empty).
  ProgressCallback progress;
};

/// A file as loadInput() read it. `value` holds the alternative of kind().
struct LoadedInput {
  /// The alternatives, in the order of InputKind.
  using Value = std::variant<MeshInput, PointSetInput, LevelSetInput, FieldInput, VdbGridsInput,
                             BSplineCurve, BSplineSurface, PolylinesInput, SupportFunctionDocument>;

  std::filesystem::path path;
  Value value;

  InputKind kind() const { return static_cast<InputKind>(value.index()); }

  /// Moves the value out as `T`; throws RuntimeFailure (a programming error) when the file was
  /// loaded as another kind.
  template <typename T>
  T take() &&;
};

/// Reads `path` as the first of these that `accepted` contains and the file holds:
/// - .vdb: Field when the file stores a field (its distance grid, the grid findGrid() selects,
///   carries kFieldKindMetadata), or when LevelSet is not accepted and the file holds a float
///   grid (built with ApproximantField::fromLevelSet() from selectGrid()'s choice, or the grid
///   named options.gridName); then LevelSet; then VdbGrids. The grids are read once.
/// - PLY: Mesh when it has faces; then PointSet (its vertices); then Mesh (without faces).
/// - OBJ, STL: Mesh. .xyz: PointSet. JSON: Curve, Surface, Polylines or SupportFunction by its
///   "type" (a support-function document is checked as readSupportFunctionJson() checks it).
/// Throws InputError naming the file when it does not exist, is a directory, cannot be read or is
/// empty; when neither its content nor its extension is one of the formats above ("cannot tell
/// what ... is"); when it holds a kind `accepted` lacks ("'f.json' is a B-spline surface;
/// <purpose> must be a B-spline curve (.json) or ..."); and as the format's own reader does for
/// malformed, truncated or non-finite content (with the line or byte offset), and for a .vdb
/// without a suitable grid (listing its grids) or a field with missing or mismatched companion
/// grids. `accepted` must not be empty.
LoadedInput loadInput(const std::filesystem::path& path, InputKinds accepted,
                      const LoadOptions& options = {});

/// The InputKind whose alternative in LoadedInput::Value is `T`.
template <typename T>
constexpr InputKind inputKindOf();

/// loadInput() accepting only the kind of `T`, returning the value itself:
/// loadInputAs<BSplineCurve>(path, options).
template <typename T>
T loadInputAs(const std::filesystem::path& path, const LoadOptions& options = {});

/// The usual name of a kind with its files, for messages: "a B-spline curve (.json)".
std::string describeInputKind(InputKind kind);

// ---- implementation of the templates ----------------------------------------------------------

namespace detail {
template <typename T, typename Variant, std::size_t Index = 0>
constexpr std::size_t variantIndexOf() {
  if constexpr (Index >= std::variant_size_v<Variant>) {
    static_assert(Index < std::variant_size_v<Variant>, "not an alternative of LoadedInput");
    return Index;
  } else if constexpr (std::is_same_v<T, std::variant_alternative_t<Index, Variant>>) {
    return Index;
  } else {
    return variantIndexOf<T, Variant, Index + 1>();
  }
}
[[noreturn]] void throwWrongInputKind(const std::filesystem::path& path, InputKind loaded,
                                      InputKind wanted);
}  // namespace detail

template <typename T>
constexpr InputKind inputKindOf() {
  return static_cast<InputKind>(detail::variantIndexOf<T, LoadedInput::Value>());
}

static_assert(inputKindOf<MeshInput>() == InputKind::Mesh &&
                  inputKindOf<PointSetInput>() == InputKind::PointSet &&
                  inputKindOf<LevelSetInput>() == InputKind::LevelSet &&
                  inputKindOf<FieldInput>() == InputKind::Field &&
                  inputKindOf<VdbGridsInput>() == InputKind::VdbGrids &&
                  inputKindOf<BSplineCurve>() == InputKind::Curve &&
                  inputKindOf<BSplineSurface>() == InputKind::Surface &&
                  inputKindOf<PolylinesInput>() == InputKind::Polylines &&
                  inputKindOf<SupportFunctionDocument>() == InputKind::SupportFunction,
              "LoadedInput::Value lists its alternatives in the order of InputKind");

template <typename T>
T LoadedInput::take() && {
  if (!std::holds_alternative<T>(value)) {
    detail::throwWrongInputKind(path, kind(), inputKindOf<T>());
  }
  return std::get<T>(std::move(value));
}

template <typename T>
T loadInputAs(const std::filesystem::path& path, const LoadOptions& options) {
  return loadInput(path, {inputKindOf<T>()}, options).template take<T>();
}

}  // namespace d2vdb
