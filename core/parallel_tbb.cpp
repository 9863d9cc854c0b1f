#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "core/parallel.h"

namespace penumbra {

int hardwareThreads() { return tbb::info::default_concurrency(); }

int threadsFor(int requested) {
    const int hardware = hardwareThreads();
    return requested > 0 && requested < hardware ? requested : hardware;
}

void parallelFor(size_t count, int threads, const std::function<void(size_t)>& body) {
    if (count == 0) return;
    tbb::task_arena arena(threadsFor(threads));
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, count, 1),
            [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i != r.end(); ++i) body(i);
            },
            tbb::simple_partitioner());
    });
}

}  // namespace penumbra
