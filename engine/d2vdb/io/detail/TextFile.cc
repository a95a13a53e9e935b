#include "d2vdb/io/detail/TextFile.h"

#include <fstream>
#include <sstream>
#include <system_error>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {

std::string readTextFile(const std::filesystem::path& file, const std::string& fileKind) {
  std::error_code error;
  if (!std::filesystem::exists(file, error)) {
    throw InputError(fileKind + " '" + file.string() + "' does not exist");
  }
  if (std::filesystem::is_directory(file, error)) {
    throw InputError(fileKind + " '" + file.string() + "' is a directory, not a file");
  }
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in || in.bad()) throw InputError(fileKind + " '" + file.string() + "' cannot be read");
  return text.str();
}

}  // namespace d2vdb::detail
