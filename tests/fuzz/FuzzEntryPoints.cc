#include "fuzz/FuzzEntryPoints.h"

#include <openvdb/openvdb.h>

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>

#include <unistd.h>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/io/FieldGrids.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/PolylineFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/detail/VdbStream.h"
#include "d2vdb/mesh/MeshMeasures.h"
#include "d2vdb/mesh/MeshValidation.h"
#include "d2vdb/mesh/detail/ObjFormat.h"
#include "d2vdb/mesh/detail/PlyFormat.h"
#include "d2vdb/mesh/detail/StlFormat.h"

namespace d2vdb::fuzz {
namespace {

std::string_view text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// What `d2vdb info` reports on a mesh: the validation report, the box and the area.
void describeMesh(const TriangleMesh& mesh) {
  const MeshReport report = validateMesh(mesh);
  static_cast<void>(report.problems());
  static_cast<void>(boundingBox(mesh));
  static_cast<void>(surfaceArea(mesh));
}

void runObj(const std::uint8_t* data, std::size_t size) {
  describeMesh(detail::parseObj(text(data, size), "fuzz.obj"));
}

void runPly(const std::uint8_t* data, std::size_t size) {
  describeMesh(detail::parsePly(text(data, size), "fuzz.ply"));
}

void runStl(const std::uint8_t* data, std::size_t size) {
  describeMesh(detail::parseStl(text(data, size), "fuzz.stl"));
}

// A spline that was accepted must evaluate anywhere in its domain.
void runSplineJson(const std::uint8_t* data, std::size_t size) {
  const Spline spline = parseSplineJson(std::string(text(data, size)), "fuzz.json");
  if (const auto* curve = std::get_if<BSplineCurve>(&spline)) {
    for (const double fraction : {0.0, 0.3, 1.0}) {
      static_cast<void>(curve->derivatives(curve->domain().at(fraction)));
    }
  } else {
    const auto& surface = std::get<BSplineSurface>(spline);
    for (const double fraction : {0.0, 0.6, 1.0}) {
      static_cast<void>(
          surface.evaluate(surface.domainU().at(fraction), surface.domainV().at(1.0 - fraction)));
    }
  }
}

void runPolylineJson(const std::uint8_t* data, std::size_t size) {
  static_cast<void>(parsePolylines(std::string(text(data, size)), "fuzz.json"));
}

void runXyz(const std::uint8_t* data, std::size_t size) {
  static_cast<void>(parseXyz(text(data, size), "fuzz.xyz"));
}

std::vector<openvdb::GridBase::Ptr> readVdb(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(text(data, size)));
  return detail::readVdbStream(in, size, "fuzz.vdb");
}

// What `d2vdb info` reports on a .vdb file.
void runVdb(const std::uint8_t* data, std::size_t size) {
  for (const openvdb::GridBase::Ptr& grid : readVdb(data, size)) {
    static_cast<void>(grid->activeVoxelCount());
    static_cast<void>(grid->evalActiveVoxelBoundingBox());
    static_cast<void>(grid->memUsage());
    for (auto meta = grid->beginMeta(); meta != grid->endMeta(); ++meta) {
      if (meta->second) static_cast<void>(meta->second->str());
    }
  }
}

// What `d2vdb field` / `info` / `query` do with a .vdb: the field (re-read or computed from a level
// set), its coarse levels and one query.
void runField(const std::uint8_t* data, std::size_t size) {
  const std::vector<openvdb::GridBase::Ptr> grids = readVdb(data, size);
  const ApproximantField field =
      fieldFromGrids(openvdb::GridPtrVec(grids.begin(), grids.end()), "fuzz.vdb");
  field.buildCoarseLevels();
  static_cast<void>(field.statistics());
  static_cast<void>(field.approximantAt(field.domain().center()));
}

// The file name extensions the `input` target's first byte chooses from (its value modulo the
// count): none, and every extension loadInput() knows, so that recognition by content and the
// fallback to the extension are both reached.
constexpr std::array<const char*, 7> kInputExtensions = {"",     ".vdb", ".ply", ".json",
                                                         ".stl", ".obj", ".xyz"};

// The scratch folder of this process that the `input` target writes each input to (loadInput()
// reads paths, not memory); removed with everything in it when the program ends.
class InputScratchFolder {
 public:
  InputScratchFolder()
      : folder_(std::filesystem::temp_directory_path() /
                ("d2vdb-fuzz-input-" + std::to_string(static_cast<long>(::getpid())))) {
    std::filesystem::create_directories(folder_);
  }
  ~InputScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(folder_, ignored);
  }
  InputScratchFolder(const InputScratchFolder&) = delete;
  InputScratchFolder& operator=(const InputScratchFolder&) = delete;

  /// Writes `bytes` to the scratch file with the given extension and returns its path.
  std::filesystem::path write(const char* extension, const std::uint8_t* bytes,
                              std::size_t count) const {
    const std::filesystem::path path = folder_ / (std::string("input") + extension);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(count));
    if (!out) throw std::runtime_error("cannot write the fuzz scratch file " + path.string());
    return path;
  }

 private:
  std::filesystem::path folder_;
};

// What every command does with a file it is given: loadInput() accepting every kind, so that the
// content decides (a .vdb holding a level set is read as one; a stored field is read back).
void runInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  static const InputScratchFolder scratch;
  const std::filesystem::path path =
      scratch.write(kInputExtensions[data[0] % kInputExtensions.size()], data + 1, size - 1);
  LoadOptions options;
  options.purpose = "the fuzzed input";
  const LoadedInput loaded =
      loadInput(path,
                {InputKind::Mesh, InputKind::PointSet, InputKind::LevelSet, InputKind::Field,
                 InputKind::VdbGrids, InputKind::Curve, InputKind::Surface, InputKind::Polylines},
                options);
  if (const auto* mesh = std::get_if<MeshInput>(&loaded.value)) describeMesh(mesh->mesh);
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"obj", "OBJ meshes (mesh/detail/ObjFormat), then the mesh report", runObj},
      {"ply", "PLY meshes, ascii and both binary encodings (mesh/detail/PlyFormat)", runPly},
      {"stl", "STL meshes, ascii and binary (mesh/detail/StlFormat)", runStl},
      {"spline_json", "B-spline curve and surface JSON (io/SplineJson), then evaluation",
       runSplineJson},
      {"polyline_json", "polyline and slice JSON (io/PolylineFile)", runPolylineJson},
      {"xyz", "point sets in .xyz text (io/PointSetFile)", runXyz},
      {"vdb", ".vdb files (io/VdbFile), then what `info` reports", runVdb},
      {"field", ".vdb files as approximant fields (io/FieldGrids), coarse levels, a query",
       runField},
      {"input",
       "any file through io/InputFile loadInput (first byte: the file name extension), as every "
       "command reads its inputs",
       runInput},
  };
  return all;
}

const Target& target(const std::string& name) {
  for (const Target& candidate : targets()) {
    if (name == candidate.name) return candidate;
  }
  throw std::invalid_argument("no fuzz target named '" + name + "'");
}

bool accepts(const Target& target, const std::uint8_t* data, std::size_t size) {
  try {
    target.run(data, size);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace d2vdb::fuzz
