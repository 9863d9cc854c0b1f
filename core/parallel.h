// The small parallel-for interface the renderer uses. The TBB implementation
// (parallel_tbb.cpp) runs inside its own task_arena so a host's own TBB work is
// neither starved nor oversubscribed.
#pragma once

#include <cstddef>
#include <functional>

namespace penumbra {

/// Number of hardware threads.
int hardwareThreads();

/// Calls body(i) for every i in [0, count) using `threads` threads (0 = all),
/// one index per task, in no particular order. Exceptions thrown by body are
/// rethrown in the caller.
void parallelFor(size_t count, int threads, const std::function<void(size_t)>& body);

}  // namespace penumbra
