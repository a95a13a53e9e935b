// One-time initialisation of the OpenVDB library for every engine entry point that uses it.
#pragma once

namespace d2vdb::detail {

/// Registers OpenVDB's grid, metadata and transform types (openvdb::initialize()). Idempotent and
/// thread-safe; every engine function that creates, reads or writes grids calls it first, so
/// callers never need to. Never throws.
void ensureOpenVdbInitialized();

}  // namespace d2vdb::detail
