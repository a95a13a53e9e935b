#include "d2vdb/io/SupportFunctionJson.h"

#include <cmath>
#include <utility>
#include <vector>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/detail/JsonDocuments.h"
#include "d2vdb/io/detail/JsonReader.h"
#include "d2vdb/io/detail/TextFile.h"

namespace d2vdb {
namespace {

using Json = detail::Json;

constexpr int kSupportFormatVersion = 1;
constexpr const char* kBasis = "real_spherical_harmonics";

class SupportFunctionReader : public detail::JsonFieldReader {
 public:
  explicit SupportFunctionReader(std::string sourceName)
      : JsonFieldReader("support-function file", std::move(sourceName)) {}

  SupportFunctionDocument document(const Json& root) const {
    object(root, "");
    const std::string type = string(root, "type");
    if (type != kSupportFunctionJsonType) {
      fail("type", "is \"" + type + "\", expected \"" + kSupportFunctionJsonType + "\"");
    }
    const int version = integer(root, "version");
    if (version != kSupportFormatVersion) {
      fail("version", "version " + std::to_string(version) +
                          " is not supported (this reader reads version " +
                          std::to_string(kSupportFormatVersion) + ")");
    }
    rejectUnknownFields(root,
                        {"type", "version", "basis", "degree", "coefficients", "domain", "fit"},
                        kSupportFunctionJsonType);
    const std::string basis = string(root, "basis");
    if (basis != kBasis) fail("basis", "is \"" + basis + "\", expected \"" + kBasis + "\"");
    const int degree = integer(root, "degree");
    if (degree < 0 || degree > kMaxSupportDegree) {
      fail("degree", "degree " + std::to_string(degree) + " is not supported (expected 0 to " +
                         std::to_string(kMaxSupportDegree) + ")");
    }
    const Json& values = array(field(root, "coefficients", "an array of numbers"), "coefficients");
    const auto expected = static_cast<std::size_t>(harmonicCount(degree));
    if (values.size() != expected) {
      fail("coefficients", "has " + std::to_string(values.size()) + " numbers, but degree " +
                               std::to_string(degree) + " needs " + std::to_string(expected) +
                               " ((degree + 1)^2)");
    }
    Eigen::VectorXd coefficients(static_cast<Eigen::Index>(expected));
    for (std::size_t i = 0; i < expected; ++i) {
      coefficients[static_cast<Eigen::Index>(i)] =
          number(values[i], detail::elementPath("coefficients", i));
    }
    SupportFunctionDocument doc;
    doc.function = SupportFunction(degree, std::move(coefficients));
    doc.patch = domain(field(root, "domain", "an object with \"kind\""));
    if (root.contains("fit")) doc.fit = fit(object(root.at("fit"), "fit"));
    return doc;
  }

 private:
  std::optional<SphericalTriangulation> domain(const Json& value) const {
    object(value, "domain");
    const std::string kind = string(value, "kind", "domain");
    if (kind == "sphere") {
      rejectUnknownFields(value, {"kind"}, "sphere domain", "domain");
      return std::nullopt;
    }
    if (kind != "patch") {
      fail("domain.kind", "is \"" + kind + "\", expected \"sphere\" or \"patch\"");
    }
    rejectUnknownFields(value, {"kind", "normals", "triangles"}, "patch domain", "domain");
    SphericalTriangulation patch;
    const Json& normals =
        array(field(value, "normals", "an array of unit vectors", "domain"), "domain.normals");
    for (std::size_t i = 0; i < normals.size(); ++i) {
      const std::string path = detail::elementPath("domain.normals", i);
      const Eigen::Vector3d n = point(normals[i], path, 3);
      if (std::abs(n.norm() - 1.0) > 1e-9) {
        fail(path, "is not a unit vector (length " + detail::jsonNumberText(n.norm()) + ")");
      }
      patch.normals.push_back(n);
    }
    const Json& triangles =
        array(field(value, "triangles", "an array of index triples", "domain"), "domain.triangles");
    if (triangles.empty()) fail("domain.triangles", "is empty (a patch needs triangles)");
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      const std::string path = detail::elementPath("domain.triangles", t);
      const Json& corners = array(triangles[t], path);
      if (corners.size() != 3) {
        fail(path, "has " + std::to_string(corners.size()) + " indices, expected 3");
      }
      SphericalTriangulation::Triangle triangle{};
      for (std::size_t k = 0; k < 3; ++k) {
        const Json& index = corners[k];
        const std::string indexPath = detail::elementPath(path, k);
        if (!index.is_number_integer()) {
          fail(indexPath, "expected an index (integer), got " + detail::describeJsonType(index));
        }
        const auto value64 = index.get<long long>();
        if (value64 < 0 || static_cast<unsigned long long>(value64) >= patch.normals.size()) {
          fail(indexPath, "index " + std::to_string(value64) + " is out of range (there are " +
                              std::to_string(patch.normals.size()) + " normals)");
        }
        triangle[k] = static_cast<SphericalTriangulation::Index>(value64);
      }
      if (triangle[0] == triangle[1] || triangle[1] == triangle[2] || triangle[2] == triangle[0]) {
        fail(path, "repeats a corner");
      }
      patch.triangles.push_back(triangle);
    }
    return patch;
  }

  SupportFitRecord fit(const Json& value) const {
    rejectUnknownFields(value,
                        {"source", "samples", "regularization", "rms_residual", "max_residual"},
                        "fit record", "fit");
    SupportFitRecord record;
    record.source = string(value, "source", "fit");
    const Json& samples = field(value, "samples", "a count", "fit");
    if (!samples.is_number_integer() || samples.get<long long>() < 0) {
      fail("fit.samples", "expected a non-negative integer, got " + samples.dump());
    }
    record.samples = static_cast<std::uint64_t>(samples.get<long long>());
    record.regularization =
        number(field(value, "regularization", "a number", "fit"), "fit.regularization");
    record.rmsResidual =
        number(field(value, "rms_residual", "a number", "fit"), "fit.rms_residual");
    record.maxResidual =
        number(field(value, "max_residual", "a number", "fit"), "fit.max_residual");
    return record;
  }
};

}  // namespace

SupportFunctionDocument parseSupportFunctionJson(const std::string& text,
                                                 const std::string& sourceName) {
  const SupportFunctionReader reader(sourceName);
  return reader.document(reader.parse(text));
}

SupportFunctionDocument detail::supportFunctionFromJson(const Json& document,
                                                        const std::string& sourceName) {
  return SupportFunctionReader(sourceName).document(document);
}

SupportFunctionDocument readSupportFunctionJson(const std::filesystem::path& file) {
  return parseSupportFunctionJson(detail::readTextFile(file, "support-function file"),
                                  file.string());
}

std::string supportFunctionToJson(const SupportFunctionDocument& document) {
  const SupportFunction& h = document.function;
  std::string text = "{\n";
  text += "  \"type\": \"" + std::string(kSupportFunctionJsonType) + "\",\n";
  text += "  \"version\": " + std::to_string(kSupportFormatVersion) + ",\n";
  text += "  \"basis\": \"" + std::string(kBasis) + "\",\n";
  text += "  \"degree\": " + std::to_string(h.degree()) + ",\n";
  text += "  \"coefficients\": [\n";
  // One degree per line.
  for (int l = 0; l <= h.degree(); ++l) {
    text += "    ";
    for (int m = -l; m <= l; ++m) {
      text += detail::jsonNumberText(h.coefficients()[harmonicIndex(l, m)]);
      if (l < h.degree() || m < l) text += ", ";
    }
    text += "\n";
  }
  text += "  ],\n";
  if (!document.patch) {
    text += "  \"domain\": {\"kind\": \"sphere\"}";
  } else {
    const SphericalTriangulation& patch = *document.patch;
    SphericalTriangulation checked = patch;
    validateSphericalTriangulation(checked, "the patch domain");
    for (std::size_t i = 0; i < patch.normals.size(); ++i) {
      if (std::abs(patch.normals[i].norm() - 1.0) > 1e-9) {
        throw InputError("cannot write the patch domain: normal " + std::to_string(i) +
                         " is not a unit vector");
      }
    }
    text += "  \"domain\": {\n    \"kind\": \"patch\",\n    \"normals\": [\n";
    for (std::size_t i = 0; i < patch.normals.size(); ++i) {
      const Eigen::Vector3d& n = patch.normals[i];
      text += "      [" + detail::jsonNumberText(n.x()) + ", " + detail::jsonNumberText(n.y()) +
              ", " + detail::jsonNumberText(n.z()) + "]" +
              (i + 1 < patch.normals.size() ? ",\n" : "\n");
    }
    text += "    ],\n    \"triangles\": [\n";
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      const auto& tri = patch.triangles[t];
      text += "      [" + std::to_string(tri[0]) + ", " + std::to_string(tri[1]) + ", " +
              std::to_string(tri[2]) + "]" + (t + 1 < patch.triangles.size() ? ",\n" : "\n");
    }
    text += "    ]\n  }";
  }
  if (document.fit) {
    const SupportFitRecord& fit = *document.fit;
    for (const double value : {fit.regularization, fit.rmsResidual, fit.maxResidual}) {
      if (!std::isfinite(value))
        throw InputError("cannot write a fit record with a non-finite number");
    }
    text += ",\n  \"fit\": {\"source\": " + Json(fit.source).dump() +
            ", \"samples\": " + std::to_string(fit.samples) +
            ", \"regularization\": " + detail::jsonNumberText(fit.regularization) +
            ", \"rms_residual\": " + detail::jsonNumberText(fit.rmsResidual) +
            ", \"max_residual\": " + detail::jsonNumberText(fit.maxResidual) + "}";
  }
  return text + "\n}\n";
}

void writeSupportFunctionJson(const std::filesystem::path& file,
                              const SupportFunctionDocument& document) {
  const std::string text = supportFunctionToJson(document);
  writeStreamAtomically(file, [&](std::ostream& out) { out << text; });
}

}  // namespace d2vdb
