// Internal: the extension of a file name, for the readers that fall back on it.
#pragma once

#include <filesystem>
#include <string>

namespace d2vdb::detail {

/// The extension of `path` with its dot, in lower case (ASCII): ".obj" for "Bunny.OBJ", "" when
/// there is none.
inline std::string lowerExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return extension;
}

}  // namespace d2vdb::detail
