// The answer of a field file at one point, reading only the part of the file the point needs.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <string>

#include "d2vdb/io/FieldQuery.h"
#include "d2vdb/io/InputFile.h"

namespace d2vdb {

/// What answerFromFieldFile() answered and how much it read.
struct FieldFileAnswer {
  FieldAnswer answer;                ///< bitwise what answerAt() gives on the whole field
  std::string outsideMessage;        ///< for QueryStatus::OutsideDomain: outsideDomainMessage()
  bool partial = false;              ///< whether the answer came from a part of the file
  int reads = 0;                     ///< clipped reads made (0: the whole file was read)
  std::uint64_t bandVoxelsRead = 0;  ///< band voxels of the part that answered (or all)
};

/// The answer of the field in `path` at `point` (world), bitwise equal to answerAt() on the field
/// loadInputAs<FieldInput>(path, load) reads, but reading only the band voxels it needs when the
/// file holds a field written by `d2vdb field` (io/FieldGrids.h):
/// - in the band, the leaves around the point: the answer is that of the voxel nearest to it;
/// - beyond the band, the coarse levels are built over the band samples of a box around the
///   point, grown until it provably holds every sample the whole field's coarse levels consult
///   for this point: every sample within reach of the coarse cells of the levels the query passes
///   (they must not be active) and within the answer's distance of the answering cell (its
///   nearest sample). Far from the target that box can cover the whole band; then the whole
///   file is read.
/// Other inputs (level sets, whose approximants are estimated from neighbourhoods) are read
/// whole. A point outside the working domain gets QueryStatus::OutsideDomain and the message.
/// Throws InputError as loadInputAs<FieldInput>() does (naming the file), and for a non-finite
/// point.
FieldFileAnswer answerFromFieldFile(const std::filesystem::path& path, const Eigen::Vector3d& point,
                                    const LoadOptions& load);

}  // namespace d2vdb
