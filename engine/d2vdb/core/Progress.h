// Progress reporting for long-running engine operations.
#pragma once

#include <functional>
#include <string_view>

namespace d2vdb {

/// Called by long operations with the name of the current stage and the fraction done in [0, 1].
/// May be called from any thread, but never concurrently (the engine serialises its calls).
/// An empty function means "no progress reporting". A callback may throw to stop the operation:
/// the exception leaves the call that was given the callback, and nothing it would have returned
/// or written exists (files are written atomically). Stages may repeat their last fraction.
using ProgressCallback = std::function<void(std::string_view stage, double fraction)>;

}  // namespace d2vdb
