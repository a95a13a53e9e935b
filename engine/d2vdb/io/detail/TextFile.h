// Internal to the io module: loading a whole text file for a parser.
#pragma once

#include <filesystem>
#include <string>

namespace d2vdb::detail {

/// The whole content of `file`. `fileKind` names the file in messages ("point file"). Throws
/// InputError "<fileKind> '<file>' does not exist" / "is a directory" / "cannot be read".
std::string readTextFile(const std::filesystem::path& file, const std::string& fileKind);

}  // namespace d2vdb::detail
