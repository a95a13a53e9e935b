// Query result files: the columns, their CSV, JSON and binary PLY forms, and the streaming batch
// writer (QueryResultFile.h).
#include "d2vdb/io/QueryResultFile.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

/// How a column is stored.
enum class ColumnType { Real, Int, Status, Flags };

/// A group of columns: one quantity with its components (suffixes; none for a scalar).
struct ColumnGroup {
  std::string name;
  std::vector<std::string> suffixes;
  ColumnType type = ColumnType::Real;
};

const std::vector<std::string> kXyz = {"x", "y", "z"};
/// The entries of a form's matrix A, row by row (all nine: A is symmetric only up to rounding).
const std::vector<std::string> kMatrix = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};

/// The forms of a result file, in order.
std::vector<ErrorTerm> formsOf(const QueryResultOptions& options) {
  if (options.allForms) return {ErrorTerm::SDM, ErrorTerm::PDM, ErrorTerm::TDM};
  return {ErrorTerm::SDM};
}

/// The column groups of the file format (QueryResultFile.h), in order; the first (the point) has
/// bare component names x, y, z.
std::vector<ColumnGroup> columnGroups(const QueryResultOptions& options) {
  std::vector<ColumnGroup> groups = {
      {"point", kXyz, ColumnType::Real},
      {"status", {}, ColumnType::Status},
      {"level", {}, ColumnType::Int},
      {"distance", {}, ColumnType::Real},
      {"squared_distance_estimate", {}, ColumnType::Real},
      {"origin", kXyz, ColumnType::Real},
      {"footpoint", kXyz, ColumnType::Real},
      {"normal", kXyz, ColumnType::Real},
      {"tangent", kXyz, ColumnType::Real},
      {"bitangent", kXyz, ColumnType::Real},
      {"k1", {}, ColumnType::Real},
      {"k2", {}, ColumnType::Real},
      {"principal_normal", kXyz, ColumnType::Real},
      {"flags", {}, ColumnType::Flags},
      {"sdm_weights", {"1", "2", "3"}, ColumnType::Real},
  };
  for (const ErrorTerm term : formsOf(options)) {
    const std::string name = errorTermName(term);
    groups.push_back({name + "_A", kMatrix, ColumnType::Real});
    groups.push_back({name + "_b", kXyz, ColumnType::Real});
    groups.push_back({name + "_c", {}, ColumnType::Real});
  }
  return groups;
}

/// The flattened columns: names and types.
struct Columns {
  std::vector<std::string> names;
  std::vector<ColumnType> types;
};

Columns flatten(const std::vector<ColumnGroup>& groups) {
  Columns columns;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const ColumnGroup& group = groups[g];
    if (group.suffixes.empty()) {
      columns.names.push_back(group.name);
      columns.types.push_back(group.type);
    }
    for (const std::string& suffix : group.suffixes) {
      columns.names.push_back(g == 0 ? suffix : group.name + "_" + suffix);
      columns.types.push_back(group.type);
    }
  }
  return columns;
}

/// Offsets of the values in fillValues()'s layout.
constexpr int kStatus = 3, kLevel = 4, kFlags = 27, kFirstForm = 31, kFormSize = 13;

/// The values of one answer in the flattened column order (integers as exact doubles).
void fillValues(const FieldAnswer& answer, const std::vector<ErrorTerm>& forms, double* v) {
  const auto put3 = [&](int at, const Eigen::Vector3d& x) {
    v[at] = x.x();
    v[at + 1] = x.y();
    v[at + 2] = x.z();
  };
  const Approximant& a = answer.approximant;
  put3(0, answer.point);
  v[kStatus] = static_cast<double>(answer.status);
  v[kLevel] = answer.level;
  v[5] = a.distance;
  v[6] = a.form(ErrorTerm::SDM)(answer.point);
  put3(7, a.origin);
  put3(10, a.footpoint);
  put3(13, a.normal);
  put3(16, a.tangent);
  put3(19, a.bitangent());
  v[22] = a.k1;
  v[23] = a.k2;
  put3(24, a.principalNormal);
  v[kFlags] = a.flags;
  put3(28, a.sdmWeights());
  int at = kFirstForm;
  for (const ErrorTerm term : forms) {
    const QuadraticForm form = a.form(term);
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column) v[at++] = form.A(row, column);
    }
    put3(at, form.b);
    at += 3;
    v[at++] = form.c;
  }
}

void appendNumber(std::string& out, double value) {
  std::array<char, 32> buffer;
  const std::to_chars_result end =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out.append(buffer.data(), end.ptr);
}

void appendInt(std::string& out, long long value) {
  std::array<char, 24> buffer;
  const std::to_chars_result end =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out.append(buffer.data(), end.ptr);
}

/// Appends the `count` low-order bytes of `bits`, least significant first (little-endian).
void appendBytes(std::string& out, std::uint64_t bits, int count) {
  for (int i = 0; i < count; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xffu));
}

void appendLittleEndian(std::string& out, double value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  appendBytes(out, bits, 8);
}

/// Formats answers into one format's records.
class RecordWriter {
 public:
  RecordWriter(QueryResultFormat format, const QueryResultOptions& options)
      : format_(format), forms_(formsOf(options)), columns_(flatten(columnGroups(options))) {}

  std::size_t valueCount() const { return columns_.names.size(); }

  /// Appends the record of answer `index` (0-based position in the file).
  void append(std::string& out, const FieldAnswer& answer, std::uint64_t index) const {
    std::array<double, kFirstForm + 3 * kFormSize> values;
    fillValues(answer, forms_, values.data());
    const bool answered = answer.status == QueryStatus::Ok;
    if (format_ == QueryResultFormat::Csv) {
      appendCsv(out, values.data(), answer.status, answered);
    } else if (format_ == QueryResultFormat::Ply) {
      appendPly(out, values.data(), answered);
    } else {
      appendJson(out, values.data(), answer.status, answered, index);
    }
  }

  std::string header(TargetKind kind, const QueryResultOptions& options,
                     std::uint64_t count) const {
    std::string out;
    if (format_ == QueryResultFormat::Csv) {
      for (std::size_t i = 0; i < columns_.names.size(); ++i) {
        out += (i ? "," : "") + columns_.names[i];
      }
      out += '\n';
    } else if (format_ == QueryResultFormat::Ply) {
      std::string field = options.field;
      std::replace(field.begin(), field.end(), '\n', ' ');
      std::replace(field.begin(), field.end(), '\r', ' ');
      out += "ply\nformat binary_little_endian 1.0\ncomment d2vdb query results of the ";
      out += std::string(targetKindName(kind)) + " field " + field + "\n";
      out += "comment status 0 = ok, 1 = outside_domain (then NaN values, level -1)\n";
      out += "element vertex " + std::to_string(count) + "\n";
      for (std::size_t i = 0; i < columns_.names.size(); ++i) {
        const ColumnType type = columns_.types[i];
        const char* plyType = type == ColumnType::Status  ? "uchar"
                              : type == ColumnType::Int   ? "int"
                              : type == ColumnType::Flags ? "ushort"
                                                          : "double";
        out += std::string("property ") + plyType + " " + columns_.names[i] + "\n";
      }
      out += "end_header\n";
    } else {
      out += "{\"format\": \"d2vdb query results\", \"version\": 1, \"field\": ";
      out += nlohmann::json(options.field)
                 .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      out += ", \"kind\": \"" + std::string(targetKindName(kind)) + "\", \"count\": ";
      out += std::to_string(count) + ",\n \"points\": [\n";
    }
    return out;
  }

  /// The JSON file's end, with the counts known only after the last point.
  std::string footer(const QueryResultSummary& summary) const {
    if (format_ != QueryResultFormat::Json) return {};
    return std::string(summary.count > 0 ? "\n" : "") +
           " ],\n \"answered\": " + std::to_string(summary.answered) +
           ", \"outside_domain\": " + std::to_string(summary.outsideDomain) + "}\n";
  }

 private:
  void appendCsv(std::string& out, const double* v, QueryStatus status, bool answered) const {
    for (std::size_t i = 0; i < columns_.names.size(); ++i) {
      if (i > 0) out += ',';
      const ColumnType type = columns_.types[i];
      if (type == ColumnType::Status) {
        out += queryStatusName(status);
      } else if (i >= 3 && !answered) {
        continue;  // no answer: empty
      } else if (type == ColumnType::Real) {
        appendNumber(out, v[i]);
      } else {
        appendInt(out, static_cast<long long>(v[i]));
      }
    }
    out += '\n';
  }

  void appendPly(std::string& out, const double* v, bool answered) const {
    for (std::size_t i = 0; i < columns_.names.size(); ++i) {
      switch (columns_.types[i]) {
        case ColumnType::Status:
          out.push_back(static_cast<char>(static_cast<unsigned char>(v[i])));
          break;
        case ColumnType::Int:
          appendBytes(out, static_cast<std::uint32_t>(static_cast<std::int32_t>(v[i])), 4);
          break;
        case ColumnType::Flags:
          appendBytes(out, answered ? static_cast<std::uint16_t>(v[i]) : 0u, 2);
          break;
        case ColumnType::Real:
          appendLittleEndian(out,
                             (i < 3 || answered) ? v[i] : std::numeric_limits<double>::quiet_NaN());
          break;
      }
    }
  }

  void appendJson(std::string& out, const double* v, QueryStatus status, bool answered,
                  std::uint64_t index) const {
    if (index > 0) out += ",\n";
    out += "  {\"index\": ";
    appendInt(out, static_cast<long long>(index));
    out += ", \"point\": ";
    appendVector(out, v, 3);
    out += ", \"status\": \"";
    out += queryStatusName(status);
    out += '"';
    const auto key = [&](const char* name) {
      out += ", \"";
      out += name;
      out += "\": ";
    };
    const auto scalar = [&](const char* name, double value) {
      key(name);
      if (answered) {
        appendNumber(out, value);
      } else {
        out += "null";
      }
    };
    const auto vector = [&](const char* name, const double* values) {
      key(name);
      if (answered) {
        appendVector(out, values, 3);
      } else {
        out += "null";
      }
    };
    key("level");
    if (answered) {
      appendInt(out, static_cast<long long>(v[kLevel]));
    } else {
      out += "null";
    }
    scalar("distance", v[5]);
    scalar("squared_distance_estimate", v[6]);
    vector("origin", v + 7);
    vector("footpoint", v + 10);
    vector("normal", v + 13);
    vector("tangent", v + 16);
    vector("bitangent", v + 19);
    scalar("k1", v[22]);
    scalar("k2", v[23]);
    vector("principal_normal", v + 24);
    key("flags");
    if (answered) {
      appendInt(out, static_cast<long long>(v[kFlags]));
    } else {
      out += "null";
    }
    vector("sdm_weights", v + 28);
    key("forms");
    if (!answered) {
      out += "null}";
      return;
    }
    out += '{';
    for (std::size_t f = 0; f < forms_.size(); ++f) {
      const double* form = v + kFirstForm + kFormSize * static_cast<int>(f);
      out += f ? ", \"" : "\"";
      out += errorTermName(forms_[f]);
      out += "\": {\"A\": [";
      for (int row = 0; row < 3; ++row) {
        if (row) out += ", ";
        appendVector(out, form + 3 * row, 3);
      }
      out += "], \"b\": ";
      appendVector(out, form + 9, 3);
      out += ", \"c\": ";
      appendNumber(out, form[12]);
      out += '}';
    }
    out += "}}";
  }

  static void appendVector(std::string& out, const double* values, int n) {
    out += '[';
    for (int i = 0; i < n; ++i) {
      if (i) out += ", ";
      appendNumber(out, values[i]);
    }
    out += ']';
  }

  QueryResultFormat format_;
  std::vector<ErrorTerm> forms_;
  Columns columns_;
};

void count(QueryResultSummary& summary, const FieldAnswer& answer) {
  ++summary.count;
  if (answer.status != QueryStatus::Ok) {
    ++summary.outsideDomain;
    return;
  }
  ++summary.answered;
  const auto level = static_cast<std::size_t>(answer.level);
  if (summary.levels.size() <= level) summary.levels.resize(level + 1, 0);
  ++summary.levels[level];
}

void merge(QueryResultSummary& total, const QueryResultSummary& part) {
  total.count += part.count;
  total.answered += part.answered;
  total.outsideDomain += part.outsideDomain;
  if (total.levels.size() < part.levels.size()) total.levels.resize(part.levels.size(), 0);
  for (std::size_t i = 0; i < part.levels.size(); ++i) total.levels[i] += part.levels[i];
}

/// Points per formatted block, and blocks formatted (in parallel) before they are written.
constexpr std::size_t kBlockSize = 2048;
constexpr std::size_t kBlocksPerBatch = 64;

/// Writes the file: header, the records of answers 0..count-1 made by `answerRange(begin, end,
/// each)` block by block in parallel (each block into its own string, written in order), footer.
QueryResultSummary writeResults(
    const std::filesystem::path& path, TargetKind kind, std::uint64_t count,
    const QueryResultOptions& options,
    const std::function<void(std::size_t, std::size_t,
                             const std::function<void(const FieldAnswer&, std::size_t)>&)>&
        answerRange) {
  const QueryResultFormat format = queryResultFormat(path);
  const RecordWriter writer(format, options);
  QueryResultSummary summary;
  writeStreamAtomically(path, [&](std::ostream& out) {
    out << writer.header(kind, options, count);
    const std::size_t blocks = (count + kBlockSize - 1) / kBlockSize;
    std::vector<std::string> text(std::min(blocks, kBlocksPerBatch));
    std::vector<QueryResultSummary> parts(text.size());
    for (std::size_t first = 0; first < blocks; first += kBlocksPerBatch) {
      const std::size_t last = std::min(blocks, first + kBlocksPerBatch);
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(first, last, 1),
          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t block = range.begin(); block != range.end(); ++block) {
              std::string& chunk = text[block - first];
              QueryResultSummary& part = parts[block - first];
              chunk.clear();
              part = QueryResultSummary();
              const std::size_t begin = block * kBlockSize;
              const std::size_t end = std::min<std::size_t>(count, begin + kBlockSize);
              answerRange(begin, end, [&](const FieldAnswer& answer, std::size_t index) {
                writer.append(chunk, answer, index);
                d2vdb::count(part, answer);
              });
            }
          },
          tbb::simple_partitioner());
      for (std::size_t block = first; block < last; ++block) {
        out.write(text[block - first].data(),
                  static_cast<std::streamsize>(text[block - first].size()));
        merge(summary, parts[block - first]);
      }
    }
    out << writer.footer(summary);
  });
  return summary;
}

}  // namespace

QueryResultFormat queryResultFormat(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".csv") return QueryResultFormat::Csv;
  if (extension == ".json") return QueryResultFormat::Json;
  if (extension == ".ply") return QueryResultFormat::Ply;
  throw InputError("the query result file '" + path.string() +
                   "' must end in .csv, .json or .ply (the format follows the extension)");
}

std::vector<std::string> queryResultColumns(const QueryResultOptions& options) {
  return flatten(columnGroups(options)).names;
}

QueryResultSummary writeFieldQueries(const std::filesystem::path& path,
                                     const ApproximantField& field,
                                     const std::vector<Eigen::Vector3d>& points,
                                     const QueryResultOptions& options) {
  queryResultFormat(path);  // refuse an unknown extension before any work
  requireFinitePoints(points, "field query");
  return writeResults(path, field.kind(), points.size(), options,
                      [&](std::size_t begin, std::size_t end, const auto& each) {
                        ApproximantField::Accessor accessor(field);
                        for (std::size_t i = begin; i < end; ++i) {
                          each(answerAt(field, accessor, points[i]), i);
                        }
                      });
}

QueryResultSummary writeQueryAnswers(const std::filesystem::path& path, TargetKind kind,
                                     const std::vector<FieldAnswer>& answers,
                                     const QueryResultOptions& options) {
  return writeResults(path, kind, answers.size(), options,
                      [&](std::size_t begin, std::size_t end, const auto& each) {
                        for (std::size_t i = begin; i < end; ++i) each(answers[i], i);
                      });
}

}  // namespace d2vdb
