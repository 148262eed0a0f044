// canonform: the one parallel loop of the library, on OpenMP.
//
// Every parallel loop (fast marching from all sources, MDS blocks, k-means assignment, the
// distance matrix, per-mesh work in a retrieval run, the procedural generator) goes through
// parallel_for(), and every "how many threads" question through thread_count(). Results never
// depend on the number of threads: a body may only write to outputs of its own index (or to the
// state of its own worker, combined afterwards in worker order).
//
// Why OpenMP (GCC's libgomp) rather than oneTBB: it ships with the compiler, so the MeshLab
// plugins gain no run-time dependency in any host; its team's thread 0 is the calling thread,
// so progress can be reported from the thread that called (MeshLab's GUI callback must not be
// called from another thread). Built without OpenMP, the loop runs on the calling thread.
#pragma once

#include "canonform/common/errors.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace canonform {

/// Worker threads for a request: `requested` if positive, else every hardware thread (at least 1).
inline int thread_count(int requested = 0) {
    if (requested > 0) return requested;
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// How a parallel_for() runs.
struct ParallelOptions {
    int threads = 0;           ///< worker threads; 0 = thread_count() (every hardware thread)
    std::ptrdiff_t grain = 1;  ///< indices per task, and the fewest per worker (small loops use fewer workers)
    ProgressFn progress;       ///< called on the calling thread with the fraction done; false cancels
    const char* stage = "";    ///< label passed to `progress`
};

/// Workers parallel_for(n, ..., options) uses: thread_count(options.threads), at most one per
/// `grain` indices, at least 1. Size per-worker state with it.
inline int parallel_workers(std::ptrdiff_t n, const ParallelOptions& options = {}) {
    const std::ptrdiff_t grain = std::max<std::ptrdiff_t>(1, options.grain);
    const std::ptrdiff_t by_size = std::max<std::ptrdiff_t>(1, n / grain);
    return static_cast<int>(std::min<std::ptrdiff_t>(thread_count(options.threads), by_size));
}

/// Calls body(i, worker) for every i in [0, n), on parallel_workers(n, options) threads taking
/// chunks of `grain` indices in turn (dynamic schedule); `worker` in [0, workers) names the thread
/// for per-worker state, and worker 0 is the calling thread, which reports progress. The first
/// exception a body throws (Cancelled too, when `progress` returns false) stops the chunks not yet
/// started and is rethrown here once every worker has stopped.
template <class Body>
void parallel_for(std::ptrdiff_t n, Body&& body, const ParallelOptions& options = {}) {
    if (n <= 0) return;
    const std::ptrdiff_t grain = std::max<std::ptrdiff_t>(1, options.grain);
    const std::ptrdiff_t chunks = (n + grain - 1) / grain;
    const int workers = parallel_workers(n, options);
    std::atomic<bool> stop{false};
    std::atomic<std::ptrdiff_t> done{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    int last_percent = -1;
    auto run_chunk = [&](std::ptrdiff_t c, int worker) {
        if (stop.load(std::memory_order_relaxed)) return;
        try {
            const std::ptrdiff_t end = std::min(n, (c + 1) * grain);
            for (std::ptrdiff_t i = c * grain; i < end; ++i) body(i, worker);
            const std::ptrdiff_t finished = done.fetch_add(end - c * grain) + (end - c * grain);
            if (worker == 0 && options.progress) {
                const int percent = static_cast<int>(100 * finished / n);
                if (percent != last_percent) {
                    last_percent = percent;
                    report_progress(options.progress, static_cast<double>(finished) / static_cast<double>(n),
                                    options.stage);
                }
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
            stop = true;
        }
    };
#ifdef _OPENMP
    if (workers > 1) {
#pragma omp parallel num_threads(workers)
        {
            const int worker = omp_get_thread_num();
#pragma omp for schedule(dynamic, 1)
            for (std::ptrdiff_t c = 0; c < chunks; ++c) run_chunk(c, worker);
        }
    } else {
        for (std::ptrdiff_t c = 0; c < chunks; ++c) run_chunk(c, 0);
    }
#else
    for (std::ptrdiff_t c = 0; c < chunks; ++c) run_chunk(c, 0);
#endif
    if (error) std::rethrow_exception(error);
}

}  // namespace canonform
