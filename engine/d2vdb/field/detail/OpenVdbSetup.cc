#include "d2vdb/field/detail/OpenVdbSetup.h"

#include <openvdb/openvdb.h>

#include <mutex>

namespace d2vdb::detail {

void ensureOpenVdbInitialized() {
  static std::once_flag initialized;
  std::call_once(initialized, [] { openvdb::initialize(); });
}

}  // namespace d2vdb::detail
