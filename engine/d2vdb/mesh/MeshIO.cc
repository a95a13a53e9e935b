#include "d2vdb/mesh/MeshIO.h"

#include <algorithm>
#include <cmath>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/detail/FileExtension.h"
#include "d2vdb/mesh/detail/MeshFileCommon.h"
#include "d2vdb/mesh/detail/ObjFormat.h"
#include "d2vdb/mesh/detail/PlyFormat.h"
#include "d2vdb/mesh/detail/StlFormat.h"

namespace d2vdb {

using detail::parseObj;
using detail::parsePly;
using detail::parseStl;
using detail::PlyEncoding;
using detail::StlEncoding;
using detail::writeObj;
using detail::writePly;
using detail::writeStl;

MeshFormat meshFormatFromPath(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  const std::string lower = detail::lowerExtension(path);
  if (lower == ".obj") return MeshFormat::Obj;
  if (lower == ".ply") return MeshFormat::Ply;
  if (lower == ".stl") return MeshFormat::Stl;
  const std::string named =
      extension.empty() ? "has no extension" : "has the extension '" + extension + "'";
  throw InputError("'" + path.string() + "' " + named +
                   ", which is not a supported mesh format (supported: .obj, .ply, .stl)");
}

std::string meshFormatName(MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj:
      return "OBJ";
    case MeshFormat::Ply:
      return "PLY";
    case MeshFormat::Stl:
      return "STL";
  }
  return "unknown";
}

TriangleMesh readMesh(const std::filesystem::path& path) {
  return readMesh(path, meshFormatFromPath(path));
}

TriangleMesh readMesh(const std::filesystem::path& path, MeshFormat format) {
  const std::string contents = detail::readFileContents(path);
  const std::string name = path.string();
  switch (format) {
    case MeshFormat::Obj:
      return parseObj(contents, name);
    case MeshFormat::Ply:
      return parsePly(contents, name);
    case MeshFormat::Stl:
      return parseStl(contents, name);
  }
  throw RuntimeFailure("readMesh: unhandled mesh format");
}

void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh,
               const MeshWriteOptions& options) {
  writeMesh(path, mesh, VertexAttributes{}, options);
}

void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh,
               const VertexAttributes& attributes, const MeshWriteOptions& options) {
  const MeshFormat format = meshFormatFromPath(path);
  // Check the mesh first so that a mesh that cannot be written never touches the file system.
  detail::checkMeshIsWritable(mesh, meshFormatName(format).c_str());
  detail::checkVertexAttributes(mesh, attributes);
  writeStreamAtomically(path, [&](std::ostream& out) {
    switch (format) {
      case MeshFormat::Obj:
        writeObj(out, mesh, &attributes);
        break;
      case MeshFormat::Ply:
        writePly(out, mesh,
                 !options.binary     ? PlyEncoding::Ascii
                 : options.bigEndian ? PlyEncoding::BinaryBigEndian
                                     : PlyEncoding::BinaryLittleEndian,
                 &attributes);
        break;
      case MeshFormat::Stl:
        writeStl(out, mesh, options.binary ? StlEncoding::Binary : StlEncoding::Ascii);
        break;
    }
  });
}

double estimateMeshFileBytes(MeshFormat format, double vertices, double triangles,
                             const MeshFileContents& contents, const MeshWriteOptions& options) {
  constexpr double kFloatText = 15.0;  // "-1.2345679e-05": the longest shortest float form
  constexpr double kHeader = 512.0;    // the comment line, a PLY or STL header
  const double indexDigits = std::floor(std::log10(std::max(vertices, 1.0))) + 1.0;
  switch (format) {
    case MeshFormat::Obj: {
      double perVertex = 2.0 + 3.0 * (1.0 + kFloatText);                  // "v x y z\n"
      if (contents.colors) perVertex += 3.0 * (1.0 + 10.0);               // " 0.49803922"
      if (contents.normals) perVertex += 3.0 + 3.0 * (1.0 + kFloatText);  // "vn x y z\n"
      const double perIndex = contents.normals ? 3.0 + 2.0 * indexDigits : 1.0 + indexDigits;
      return kHeader + vertices * perVertex + triangles * (2.0 + 3.0 * perIndex);
    }
    case MeshFormat::Ply: {
      const double properties = 3.0 + (contents.normals ? 3.0 : 0.0) + contents.scalars;
      if (options.binary) {
        return kHeader + vertices * (4.0 * properties + (contents.colors ? 3.0 : 0.0)) +
               triangles * (1.0 + 3.0 * 4.0);
      }
      return kHeader +
             vertices *
                 (properties * (1.0 + kFloatText) + (contents.colors ? 3.0 * 4.0 : 0.0) + 1.0) +
             triangles * (2.0 + 3.0 * (1.0 + indexDigits));
    }
    case MeshFormat::Stl:
      // Binary: 50 bytes a facet; ASCII: facet normal, outer loop, three vertices, two ends.
      return options.binary
                 ? 84.0 + 50.0 * triangles
                 : kHeader + triangles * (4.0 * (16.0 + 3.0 * (1.0 + kFloatText)) + 40.0);
  }
  return kHeader;
}

}  // namespace d2vdb
