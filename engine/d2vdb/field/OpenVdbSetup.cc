#include "d2vdb/field/OpenVdbSetup.h"

#include <openvdb/openvdb.h>

#include <mutex>

namespace d2vdb {

void ensureOpenVdbInitialized() {
  static std::once_flag initialized;
  std::call_once(initialized, [] { openvdb::initialize(); });
}

}  // namespace d2vdb
