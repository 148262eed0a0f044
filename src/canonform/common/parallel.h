// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the one parallel loop of the library, on oneTBB (or std::thread without it).
//
// Every parallel loop (fast marching from all sources, MDS blocks, k-means assignment, the
// distance matrix, per-mesh work in a retrieval run, the procedural generator, the multigrid
// solver's sweeps and products over 1M non-zeros and more) goes through
// parallel_for(), and every "how many threads" question through thread_count(). Results never
// depend on the number of threads: a body may only write to outputs of its own index (or to the
// state of its own worker, combined afterwards in worker order).
//
// Why oneTBB rather than OpenMP: Debian's OpenCV (which the views area uses for SIFT) already
// runs its own parallel loops on oneTBB, so with TBB both share one pool of worker threads and
// nest without oversubscribing the cores; a second (OpenMP) pool next to it made idle threads
// spin against busy ones (more CPU time for the same work on the 2-core test machine). Progress
// is reported only from the thread that called parallel_for() (MeshLab's GUI callback must not be
// called from another thread).
//
// Without oneTBB (a core-only build, CANONFORM_HAVE_TBB undefined: CMake's CANONFORM_WITHOUT_TBB or
// no TBB found) the same loop runs on std::thread workers that take chunks in turn; since results
// never depend on the threads, they are the same.
#pragma once

#include "canonform/common/errors.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>

#if defined(CANONFORM_HAVE_TBB)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#else
#include <exception>
#include <mutex>
#include <vector>
#endif

namespace canonform {

/// Worker threads for a request: `requested` if positive, else every hardware thread (at least 1).
inline int thread_count(int requested = 0) {
    if (requested > 0) return requested;
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// How a parallel_for() runs.
struct ParallelOptions {
    int threads = 0;  ///< worker threads; 0 = thread_count() (every hardware thread)
    std::ptrdiff_t grain =
        1;                   ///< indices per task, and the fewest per worker (small loops use fewer workers)
    ProgressFn progress;     ///< called on the calling thread with the fraction done; false cancels
    const char* stage = "";  ///< label passed to `progress`
};

/// Workers parallel_for(n, ..., options) uses: thread_count(options.threads), at most one per
/// `grain` indices, at least 1. Size per-worker state with it.
inline int parallel_workers(std::ptrdiff_t n, const ParallelOptions& options = {}) {
    const std::ptrdiff_t grain = std::max<std::ptrdiff_t>(1, options.grain);
    const std::ptrdiff_t by_size = std::max<std::ptrdiff_t>(1, n / grain);
    return static_cast<int>(std::min<std::ptrdiff_t>(thread_count(options.threads), by_size));
}

/// Calls body(i, worker) for every i in [0, n), on parallel_workers(n, options) threads taking
/// chunks of `grain` indices in turn; `worker` in [0, workers) names the thread for per-worker
/// state. Progress is reported from the calling thread (which works too). The first exception a
/// body throws (Cancelled too, when `progress` returns false) cancels the chunks not yet started
/// and is rethrown here.
template <class Body>
void parallel_for(std::ptrdiff_t n, Body&& body, const ParallelOptions& options = {}) {
    if (n <= 0) return;
    const std::ptrdiff_t grain = std::max<std::ptrdiff_t>(1, options.grain);
    const int workers = parallel_workers(n, options);
    const std::thread::id caller = std::this_thread::get_id();
    std::atomic<std::ptrdiff_t> done{0};
    int last_percent = -1;
    auto run = [&](std::ptrdiff_t begin, std::ptrdiff_t end, int worker) {
        for (std::ptrdiff_t i = begin; i < end; ++i) body(i, worker);
        const std::ptrdiff_t finished = done.fetch_add(end - begin) + (end - begin);
        if (options.progress && std::this_thread::get_id() == caller) {
            const int percent = static_cast<int>(100 * finished / n);
            if (percent != last_percent) {
                last_percent = percent;
                report_progress(options.progress, static_cast<double>(finished) / static_cast<double>(n),
                                options.stage);
            }
        }
    };
    if (workers <= 1) {
        for (std::ptrdiff_t begin = 0; begin < n; begin += grain) run(begin, std::min(n, begin + grain), 0);
        return;
    }
#if defined(CANONFORM_HAVE_TBB)
    tbb::task_arena arena(workers);
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::ptrdiff_t>(0, n, static_cast<std::size_t>(grain)),
            [&](const tbb::blocked_range<std::ptrdiff_t>& r) {
                const int w = tbb::this_task_arena::current_thread_index();
                run(r.begin(), r.end(), std::min(std::max(w, 0), workers - 1));
            },
            tbb::simple_partitioner());
    });
#else
    // Workers 1.. on threads, worker 0 the caller; chunks taken in turn; the first exception
    // stops the chunks not yet started and is rethrown here.
    std::atomic<std::ptrdiff_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto work = [&](int worker) {
        try {
            for (std::ptrdiff_t begin; !failed && (begin = next.fetch_add(grain)) < n;)
                run(begin, std::min(n, begin + grain), worker);
        } catch (...) {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
            failed = true;
        }
    };
    std::vector<std::thread> threads;
    threads.reserve(static_cast<std::size_t>(workers - 1));
    for (int w = 1; w < workers; ++w) threads.emplace_back(work, w);
    work(0);
    for (auto& t : threads) t.join();
    if (error) std::rethrow_exception(error);
#endif
}

/// body(begin, end) for the ranges [0, chunk), [chunk, 2 chunk), ... of [0, n): on
/// thread_count(threads) threads when `share` is true and there are two ranges or more, else all
/// on the calling thread (no pool for small work). For per-index work whose values do not depend
/// on which thread does a range (the ranges are fixed by n and chunk alone).
template <class Body>
void parallel_ranges(std::ptrdiff_t n, std::ptrdiff_t chunk, bool share, int threads, const Body& body) {
    if (n <= 0) return;
    const std::ptrdiff_t ranges = (n + chunk - 1) / chunk;
    const auto run = [&](std::ptrdiff_t r, int) {
        const std::ptrdiff_t begin = r * chunk;
        body(begin, std::min(n, begin + chunk));
    };
    if (!share || ranges < 2) {
        for (std::ptrdiff_t r = 0; r < ranges; ++r) run(r, 0);
        return;
    }
    ParallelOptions o;
    o.threads = threads;
    parallel_for(ranges, run, o);
}

/// Rows (of a matrix, vertices of a mesh) from which per-row work is shared out (parallel_rows).
constexpr std::ptrdiff_t kShareRowsFrom = 131072;

/// body(begin, end) over [0, n) in ranges of 65,536 rows, on thread_count(threads) threads from
/// kShareRowsFrom rows (large meshes), else on the calling thread. Only for per-row work whose
/// values do not depend on which thread does a range.
template <class Body>
void parallel_rows(std::ptrdiff_t n, int threads, const Body& body) {
    parallel_ranges(n, kShareRowsFrom / 2, n >= kShareRowsFrom, threads, body);
}

}  // namespace canonform
