// The small parallel-for interface the renderer uses. The TBB implementation
// (parallel_tbb.cpp) runs inside its own task_arena so a host's own TBB work is
// neither starved nor oversubscribed.
#pragma once

#include <cstddef>
#include <functional>

namespace penumbra {

/// Number of hardware threads.
int hardwareThreads();

/// The threads parallelFor runs for a request of `requested`: all hardware
/// threads for 0, else the request up to that many (more would only wait for
/// a core, and TBB refuses them with a warning on stderr).
int threadsFor(int requested);

/// Calls body(i) for every i in [0, count) using threadsFor(threads) threads,
/// one index per task, in no particular order. Exceptions thrown by body are
/// rethrown in the caller.
void parallelFor(size_t count, int threads, const std::function<void(size_t)>& body);

}  // namespace penumbra
