// Tests of field queries at many points (io/FieldQuery.h), their result files
// (io/QueryResultFile.h) and single queries from a part of a field file (io/FieldFileQuery.h):
// against the analytic sphere, against one another point by point, bitwise across thread counts,
// and the refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/WithThreads.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldFileQuery.h"
#include "d2vdb/io/FieldQuery.h"
#include "d2vdb/io/QueryResultFile.h"
#include "d2vdb/io/VdbFile.h"
#include "io/IoTestSupport.h"

namespace {

using d2vdb::ApproximantField;
using d2vdb::FieldAnswer;
using d2vdb::QueryStatus;
using d2vdb::test::sameBits;
using Eigen::Vector3d;

constexpr double kRadius = 1.0;
constexpr double kVoxel = 0.04;

const d2vdb::Sphere& sphere() {
  static const d2vdb::Sphere shape(Vector3d::Zero(), kRadius);
  return shape;
}

openvdb::FloatGrid::Ptr sphereLevelSet() {
  d2vdb::PrimitiveLevelSetOptions options;
  options.voxelSize = kVoxel;
  return d2vdb::primitiveLevelSet(sphere(), options);
}

const ApproximantField& sphereField() {
  static const ApproximantField field = ApproximantField::fromLevelSet(sphereLevelSet());
  return field;
}

/// Random directions at distances from the centre drawn from [lo, hi].
std::vector<Vector3d> shellPoints(std::size_t count, double lo, double hi, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> radius(lo, hi);
  std::vector<Vector3d> points;
  for (std::size_t i = 0; i < count; ++i) {
    const Vector3d direction = Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
    points.push_back(radius(random) * direction);
  }
  return points;
}

/// Points in the band, beyond it (outside and inside the sphere) and one outside the domain.
std::vector<Vector3d> mixedPoints() {
  std::vector<Vector3d> points = shellPoints(60, 0.97, 1.03, 1);
  for (const Vector3d& p : shellPoints(30, 1.2, 1.9, 2)) points.push_back(p);
  for (const Vector3d& p : shellPoints(20, 0.45, 0.8, 3)) points.push_back(p);
  points.emplace_back(50.0, 0.0, 0.0);
  return points;
}

bool sameVector(const Vector3d& a, const Vector3d& b) {
  return sameBits(a.x(), b.x()) && sameBits(a.y(), b.y()) && sameBits(a.z(), b.z());
}

/// Every field of two answers, bit for bit.
void expectSameAnswer(const FieldAnswer& a, const FieldAnswer& b, const std::string& where) {
  EXPECT_EQ(a.status, b.status) << where;
  EXPECT_EQ(a.level, b.level) << where;
  EXPECT_TRUE(sameVector(a.point, b.point)) << where;
  const d2vdb::Approximant &x = a.approximant, &y = b.approximant;
  EXPECT_EQ(x.kind, y.kind) << where;
  EXPECT_EQ(x.flags, y.flags) << where;
  EXPECT_TRUE(sameBits(x.distance, y.distance))
      << where << ": " << x.distance << " vs " << y.distance;
  EXPECT_TRUE(sameVector(x.origin, y.origin)) << where;
  EXPECT_TRUE(sameVector(x.footpoint, y.footpoint)) << where;
  EXPECT_TRUE(sameVector(x.normal, y.normal)) << where;
  EXPECT_TRUE(sameVector(x.tangent, y.tangent)) << where;
  EXPECT_TRUE(sameBits(x.k1, y.k1) && sameBits(x.k2, y.k2)) << where;
  EXPECT_TRUE(sameVector(x.principalNormal, y.principalNormal)) << where;
}

TEST(FieldQueryTest, BatchAnswersArePointAnswersAndTheSphere) {
  const ApproximantField& field = sphereField();
  const std::vector<Vector3d> points = mixedPoints();
  const std::vector<FieldAnswer> batch = d2vdb::answerAll(field, points);
  ASSERT_EQ(batch.size(), points.size());
  ApproximantField::Accessor accessor(field);
  int band = 0, beyond = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string where = "point " + std::to_string(i);
    expectSameAnswer(batch[i], d2vdb::answerAt(field, accessor, points[i]), where);
    if (batch[i].status != QueryStatus::Ok) continue;
    // Against the exact sphere: distance |p| - R, footpoint R p / |p|, normal p / |p|, k = 1/R.
    const d2vdb::Approximant& a = batch[i].approximant;
    const Vector3d& p = points[i];
    const double tolerance =
        batch[i].level == 0 ? 0.05 * kVoxel : field.coarseDistanceErrorBound(batch[i].level);
    (batch[i].level == 0 ? band : beyond)++;
    EXPECT_NEAR(a.distance, p.norm() - kRadius, tolerance) << where;
    EXPECT_LE((a.footpoint - kRadius * p.normalized()).norm(),
              batch[i].level == 0 ? 0.1 * kVoxel : tolerance)
        << where;
    // Beyond the band the normal points from the footpoint to the point, so its angle to the
    // exact normal is bounded by the footpoint's error seen from the point.
    const double depth = std::abs(p.norm() - kRadius);
    const double angle = batch[i].level == 0
                             ? 1.0 * M_PI / 180.0
                             : std::atan2(tolerance, std::max(depth - tolerance, 0.0));
    EXPECT_GE(a.normal.dot(p.normalized()), std::cos(angle) - 1e-12) << where;
    EXPECT_NEAR(a.k1, 1.0 / kRadius, 0.03 / kRadius) << where;
    EXPECT_NEAR(a.k2, 1.0 / kRadius, 0.03 / kRadius) << where;
    EXPECT_NEAR(std::abs(a.tangent.dot(a.normal)), 0.0, 1e-9) << where;
  }
  EXPECT_GE(band, 50);
  EXPECT_GE(beyond, 40);
  EXPECT_EQ(batch.back().status, QueryStatus::OutsideDomain);
  EXPECT_EQ(batch.back().level, -1);
}

TEST(FieldQueryTest, NonFinitePointsAreRefusedWithTheirIndex) {
  std::vector<Vector3d> points = {Vector3d(1, 0, 0), Vector3d(0, std::nan(""), 0)};
  d2vdb::test::expectInputError([&] { d2vdb::answerAll(sphereField(), points); },
                                {"query point 1"});
}

// ---- result files ------------------------------------------------------------------------------

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

/// The flattened values answerAll() implies for a column, computed here from the answer.
double expectedColumn(const FieldAnswer& answer, const std::string& column) {
  const d2vdb::Approximant& a = answer.approximant;
  const auto component = [](const Vector3d& v, char axis) { return v[axis - 'x']; };
  if (column.size() == 1) return component(answer.point, column[0]);
  if (column == "level") return answer.level;
  if (column == "distance") return a.distance;
  if (column == "squared_distance_estimate") return a.form(d2vdb::ErrorTerm::SDM)(answer.point);
  if (column == "k1") return a.k1;
  if (column == "k2") return a.k2;
  if (column == "flags") return a.flags;
  const std::size_t split = column.rfind('_');
  const std::string group = column.substr(0, split), suffix = column.substr(split + 1);
  if (group == "origin") return component(a.origin, suffix[0]);
  if (group == "footpoint") return component(a.footpoint, suffix[0]);
  if (group == "normal") return component(a.normal, suffix[0]);
  if (group == "tangent") return component(a.tangent, suffix[0]);
  if (group == "bitangent") return component(a.bitangent(), suffix[0]);
  if (group == "principal_normal") return component(a.principalNormal, suffix[0]);
  if (group == "sdm_weights") return a.sdmWeights()[suffix[0] - '1'];
  const d2vdb::ErrorTerm term = group[0] == 's'   ? d2vdb::ErrorTerm::SDM
                                : group[0] == 'p' ? d2vdb::ErrorTerm::PDM
                                                  : d2vdb::ErrorTerm::TDM;
  const d2vdb::QuadraticForm form = a.form(term);
  if (group.size() == 5 && group.substr(3) == "_A") {
    return form.A(suffix[0] - 'x', suffix[1] - 'x');
  }
  if (group.substr(3) == "_b") return component(form.b, suffix[0]);
  if (column.substr(3) == "_c") return form.c;
  ADD_FAILURE() << "unknown column " << column;
  return 0.0;
}

class QueryResultFileTest : public d2vdb::test::ScratchDirectoryTest {};

TEST_F(QueryResultFileTest, CsvHoldsEveryAnswerBitForBit) {
  const std::vector<Vector3d> points = mixedPoints();
  const std::vector<FieldAnswer> answers = d2vdb::answerAll(sphereField(), points);
  d2vdb::QueryResultOptions options;
  options.allForms = true;
  const d2vdb::QueryResultSummary summary =
      d2vdb::writeFieldQueries(file("r.csv"), sphereField(), points, options);
  EXPECT_EQ(summary.count, points.size());
  EXPECT_EQ(summary.outsideDomain, 1u);
  EXPECT_EQ(summary.answered, points.size() - 1);
  std::stringstream text(d2vdb::test::readWholeFile(file("r.csv")));
  std::string line;
  std::getline(text, line);
  const std::vector<std::string> columns = splitCsv(line);
  EXPECT_EQ(columns, d2vdb::queryResultColumns(options));
  ASSERT_EQ(columns.size(), 3u + 2 + 2 + 5 * 3 + 2 + 3 + 1 + 3 + 3 * 13);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(std::getline(text, line));
    const std::vector<std::string> fields = splitCsv(line);
    ASSERT_EQ(fields.size(), columns.size()) << line;
    const bool answered = answers[i].status == QueryStatus::Ok;
    EXPECT_EQ(fields[3], answered ? "ok" : "outside_domain");
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c == 3) continue;
      if (!answered && c > 3) {
        EXPECT_TRUE(fields[c].empty()) << columns[c];
        continue;
      }
      const double value = std::strtod(fields[c].c_str(), nullptr);
      EXPECT_TRUE(sameBits(value, expectedColumn(answers[i], columns[c])))
          << "point " << i << " column " << columns[c] << ": " << fields[c];
    }
  }
  EXPECT_FALSE(std::getline(text, line));
}

TEST_F(QueryResultFileTest, JsonHoldsEveryAnswerBitForBit) {
  const std::vector<Vector3d> points = mixedPoints();
  const std::vector<FieldAnswer> answers = d2vdb::answerAll(sphereField(), points);
  d2vdb::QueryResultOptions options;
  options.field = "sphere \"field\".vdb";
  d2vdb::writeFieldQueries(file("r.json"), sphereField(), points, options);
  const auto document = nlohmann::json::parse(d2vdb::test::readWholeFile(file("r.json")));
  EXPECT_EQ(document["format"], "d2vdb query results");
  EXPECT_EQ(document["field"], options.field);
  EXPECT_EQ(document["kind"], "surface");
  EXPECT_EQ(document["count"], points.size());
  EXPECT_EQ(document["outside_domain"], 1);
  ASSERT_EQ(document["points"].size(), points.size());
  const auto vector = [](const nlohmann::json& v) {
    return Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    const nlohmann::json& p = document["points"][i];
    const FieldAnswer& answer = answers[i];
    EXPECT_EQ(p["index"], i);
    EXPECT_TRUE(sameVector(vector(p["point"]), points[i]));
    if (answer.status != QueryStatus::Ok) {
      EXPECT_EQ(p["status"], "outside_domain");
      EXPECT_TRUE(p["distance"].is_null() && p["footpoint"].is_null() && p["level"].is_null());
      continue;
    }
    const d2vdb::Approximant& a = answer.approximant;
    EXPECT_EQ(p["status"], "ok");
    EXPECT_EQ(p["level"], answer.level);
    EXPECT_EQ(p["flags"], a.flags);
    EXPECT_TRUE(sameBits(p["distance"].get<double>(), a.distance));
    EXPECT_TRUE(sameVector(vector(p["footpoint"]), a.footpoint));
    EXPECT_TRUE(sameVector(vector(p["normal"]), a.normal));
    EXPECT_TRUE(sameVector(vector(p["tangent"]), a.tangent));
    EXPECT_TRUE(sameVector(vector(p["bitangent"]), a.bitangent()));
    EXPECT_TRUE(sameBits(p["k1"].get<double>(), a.k1) && sameBits(p["k2"].get<double>(), a.k2));
    const d2vdb::QuadraticForm sdm = a.form(d2vdb::ErrorTerm::SDM);
    for (int row = 0; row < 3; ++row) {
      EXPECT_TRUE(sameVector(vector(p["forms"]["sdm"]["A"][row]), sdm.A.row(row).transpose()));
    }
    EXPECT_TRUE(sameVector(vector(p["forms"]["sdm"]["b"]), sdm.b));
    EXPECT_TRUE(sameBits(p["forms"]["sdm"]["c"].get<double>(), sdm.c));
    EXPECT_FALSE(p["forms"].contains("pdm"));
  }
}

/// The vertex rows of a binary little-endian PLY written by writeFieldQueries(): column names,
/// their types and each row's values as doubles.
struct PlyTable {
  std::vector<std::string> names, types;
  std::vector<std::vector<double>> rows;
};

PlyTable readPly(const std::string& bytes) {
  PlyTable table;
  std::size_t at = 0, count = 0;
  std::string line;
  while (line != "end_header") {
    const std::size_t end = bytes.find('\n', at);
    line = bytes.substr(at, end - at);
    at = end + 1;
    std::istringstream words(line);
    std::string word, type, name;
    words >> word;
    if (word == "element") words >> name >> count;
    if (word == "property") {
      words >> type >> name;
      table.types.push_back(type);
      table.names.push_back(name);
    }
  }
  for (std::size_t r = 0; r < count; ++r) {
    std::vector<double> row;
    for (const std::string& type : table.types) {
      const auto take = [&](auto value) {
        std::memcpy(&value, bytes.data() + at, sizeof value);  // the test host is little-endian
        at += sizeof value;
        row.push_back(static_cast<double>(value));
      };
      if (type == "double") take(double());
      if (type == "uchar") take(std::uint8_t());
      if (type == "int") take(std::int32_t());
      if (type == "ushort") take(std::uint16_t());
    }
    table.rows.push_back(row);
  }
  EXPECT_EQ(at, bytes.size());
  return table;
}

TEST_F(QueryResultFileTest, PlyHoldsEveryAnswerBitForBit) {
  const std::vector<Vector3d> points = mixedPoints();
  const std::vector<FieldAnswer> answers = d2vdb::answerAll(sphereField(), points);
  d2vdb::writeFieldQueries(file("r.PLY"), sphereField(), points, {});
  const PlyTable table = readPly(d2vdb::test::readWholeFile(file("r.PLY")));
  EXPECT_EQ(table.names, d2vdb::queryResultColumns({}));
  ASSERT_EQ(table.rows.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool answered = answers[i].status == QueryStatus::Ok;
    EXPECT_EQ(table.rows[i][3], answered ? 0.0 : 1.0);
    for (std::size_t c = 0; c < table.names.size(); ++c) {
      if (c == 3) continue;
      const double value = table.rows[i][c];
      if (!answered && c > 3) {
        if (table.names[c] == "level") {
          EXPECT_EQ(value, -1.0);
        }
        if (table.types[c] == "double") {
          EXPECT_TRUE(std::isnan(value)) << table.names[c];
        }
        continue;
      }
      EXPECT_TRUE(sameBits(value, expectedColumn(answers[i], table.names[c])))
          << "point " << i << " column " << table.names[c];
    }
  }
}

TEST_F(QueryResultFileTest, FilesAreBitwiseTheSameForAnyThreadCount) {
  // Enough points for many blocks of the parallel writer.
  std::vector<Vector3d> points = shellPoints(9000, 0.9, 1.6, 4);
  points.emplace_back(-60.0, 2.0, 0.0);
  for (const char* name : {"t.csv", "t.json", "t.ply"}) {
    const std::string one = d2vdb::test::withThreads(1, [&] {
      d2vdb::writeFieldQueries(file(std::string("1") + name), sphereField(), points, {});
      return d2vdb::test::readWholeFile(file(std::string("1") + name));
    });
    const std::string two = d2vdb::test::withThreads(2, [&] {
      d2vdb::writeFieldQueries(file(std::string("2") + name), sphereField(), points, {});
      return d2vdb::test::readWholeFile(file(std::string("2") + name));
    });
    EXPECT_GT(one.size(), points.size() * 100) << name;
    EXPECT_TRUE(one == two) << name;
    // Answers computed first and written afterwards give the same bytes.
    d2vdb::writeQueryAnswers(file(std::string("a") + name), d2vdb::TargetKind::Surface,
                             d2vdb::answerAll(sphereField(), points), {});
    EXPECT_TRUE(d2vdb::test::readWholeFile(file(std::string("a") + name)) == one) << name;
  }
}

TEST_F(QueryResultFileTest, RefusalsLeaveAnExistingFileUnchanged) {
  const std::vector<Vector3d> points = shellPoints(10, 0.9, 1.1, 5);
  d2vdb::test::expectInputError(
      [&] { d2vdb::writeFieldQueries(file("r.txt"), sphereField(), points, {}); },
      {"r.txt", ".csv, .json or .ply"});
  EXPECT_FALSE(std::filesystem::exists(file("r.txt")));
  write("r.csv", "precious");
  std::vector<Vector3d> bad = points;
  bad.emplace_back(0.0, std::numeric_limits<double>::infinity(), 0.0);
  d2vdb::test::expectInputError(
      [&] { d2vdb::writeFieldQueries(file("r.csv"), sphereField(), bad, {}); }, {"query point 10"});
  EXPECT_EQ(d2vdb::test::readWholeFile(file("r.csv")), "precious");
  // A directory that does not exist: a run failure, nothing written.
  EXPECT_THROW(d2vdb::writeFieldQueries(file("absent/r.csv"), sphereField(), points, {}),
               d2vdb::RuntimeFailure);
}

// ---- single queries from part of a file ---------------------------------------------------------

class FieldFileQueryTest : public d2vdb::test::ScratchDirectoryTest {};

TEST_F(FieldFileQueryTest, PartialReadsAnswerBitwiseAsTheWholeFile) {
  d2vdb::writeField(file("sphere-field.vdb"), sphereField());
  const ApproximantField whole = d2vdb::readField(file("sphere-field.vdb"));
  ApproximantField::Accessor accessor(whole);
  std::vector<Vector3d> points = shellPoints(12, 0.96, 1.04, 6);                // the band
  for (const Vector3d& p : shellPoints(12, 1.16, 1.5, 7)) points.push_back(p);  // just beyond
  for (const Vector3d& p : shellPoints(6, 0.3, 0.85, 8)) points.push_back(p);   // inside
  points.emplace_back(1.9, 1.9, 1.9);  // far: a corner of the domain
  std::vector<int> levels;
  int partialBeyond = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const d2vdb::FieldFileAnswer read =
        d2vdb::answerFromFieldFile(file("sphere-field.vdb"), points[i], {});
    const FieldAnswer reference = d2vdb::answerAt(whole, accessor, points[i]);
    expectSameAnswer(read.answer, reference, "point " + std::to_string(i));
    levels.push_back(reference.level);
    if (reference.level == 0) {
      EXPECT_TRUE(read.partial) << i;
      EXPECT_EQ(read.reads, 1) << i;
      EXPECT_LT(read.bandVoxelsRead, whole.distanceGrid()->activeVoxelCount() / 4) << i;
    } else if (read.partial) {
      ++partialBeyond;
    }
  }
  EXPECT_GE(*std::max_element(levels.begin(), levels.end()), 3);
  EXPECT_GE(std::count(levels.begin(), levels.end(), 0), 10);
  EXPECT_GE(partialBeyond, 6);  // near the band a part suffices beyond it too
  // Outside the domain: the status and the field's own message, without reading voxels.
  const d2vdb::FieldFileAnswer outside =
      d2vdb::answerFromFieldFile(file("sphere-field.vdb"), Vector3d(40, 0, 0), {});
  EXPECT_EQ(outside.answer.status, QueryStatus::OutsideDomain);
  EXPECT_EQ(outside.reads, 0);
  try {
    whole.approximantAt(Vector3d(40, 0, 0));
    ADD_FAILURE() << "no error outside the domain";
  } catch (const d2vdb::InputError& error) {
    EXPECT_EQ(outside.outsideMessage, error.what());
  }
}

TEST_F(FieldFileQueryTest, LevelSetsAndBadFilesAreReadWhole) {
  d2vdb::writeVdb(file("sphere.vdb"), {sphereLevelSet()});
  const Vector3d point(0.2, 0.99, 0.1);
  const d2vdb::FieldFileAnswer read = d2vdb::answerFromFieldFile(file("sphere.vdb"), point, {});
  EXPECT_FALSE(read.partial);
  ApproximantField::Accessor accessor(sphereField());
  expectSameAnswer(read.answer, d2vdb::answerAt(sphereField(), accessor, point), "level set");
  // A truncated field file fails as the whole read does.
  d2vdb::writeField(file("f.vdb"), sphereField());
  const std::string bytes = d2vdb::test::readWholeFile(file("f.vdb"));
  write("cut.vdb", bytes.substr(0, bytes.size() / 2));
  d2vdb::test::expectInputError([&] { d2vdb::answerFromFieldFile(file("cut.vdb"), point, {}); },
                                {"cut.vdb"});
  d2vdb::test::expectInputError([&] { d2vdb::answerFromFieldFile(file("absent.vdb"), point, {}); },
                                {"absent.vdb"});
  d2vdb::test::expectInputError(
      [&] { d2vdb::answerFromFieldFile(file("f.vdb"), Vector3d(0, NAN, 0), {}); }, {"not finite"});
}

}  // namespace
