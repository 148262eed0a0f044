// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/common/parallel.h"

#include <gtest/gtest.h>

#include <numeric>
#include <set>
#include <stdexcept>
#include <vector>

using namespace canonform;

TEST(Parallel, ThreadCountRule) {
    EXPECT_EQ(thread_count(3), 3);
    EXPECT_GE(thread_count(0), 1);
    EXPECT_EQ(thread_count(-1), thread_count(0));
    ParallelOptions o;
    o.threads = 8;
    o.grain = 100;
    EXPECT_EQ(parallel_workers(150, o), 1);  // fewer than two grains: one worker
    EXPECT_EQ(parallel_workers(10000, o), 8);
    EXPECT_EQ(parallel_workers(0, o), 1);
}

TEST(Parallel, EveryIndexOnceWhateverTheThreads) {
    for (int threads : {1, 2, 4}) {
        for (std::ptrdiff_t grain : {1, 7, 1000}) {
            std::vector<int> hits(5003, 0);
            ParallelOptions o;
            o.threads = threads;
            o.grain = grain;
            std::vector<int> per_worker(static_cast<size_t>(parallel_workers(5003, o)), 0);
            parallel_for(
                5003,
                [&](std::ptrdiff_t i, int w) {
                    ++hits[static_cast<size_t>(i)];
                    ++per_worker[static_cast<size_t>(w)];
                },
                o);
            EXPECT_EQ(std::count(hits.begin(), hits.end(), 1), 5003)
                << threads << " threads, grain " << grain;
            EXPECT_EQ(std::accumulate(per_worker.begin(), per_worker.end(), 0), 5003);
        }
    }
}

TEST(Parallel, FirstErrorIsRethrownAndStopsTheRest) {
    ParallelOptions o;
    o.threads = 2;
    std::vector<char> done(100000, 0);
    EXPECT_THROW(parallel_for(
                     100000,
                     [&](std::ptrdiff_t i, int) {
                         if (i == 10) throw std::invalid_argument("index 10");
                         done[static_cast<size_t>(i)] = 1;
                     },
                     o),
                 std::invalid_argument);
    // Chunks not yet started when the error came are skipped.
    EXPECT_LT(std::count(done.begin(), done.end(), 1), 100000);
}

TEST(Parallel, ProgressOnTheCallingThreadAndCancellation) {
    ParallelOptions o;
    o.threads = 2;
    std::vector<double> seen;
    o.progress = [&](double f, const char*) {
        seen.push_back(f);
        return true;
    };
    parallel_for(
        1000, [](std::ptrdiff_t, int) {}, o);
    ASSERT_FALSE(seen.empty());
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    EXPECT_LE(seen.back(), 1.0);
    o.progress = [](double f, const char*) { return f < 0.2; };
    EXPECT_THROW(parallel_for(
                     1000, [](std::ptrdiff_t, int) {}, o),
                 Cancelled);
}

TEST(Parallel, RangesAreFixedAndSharedOnlyWhenAsked) {
    // parallel_ranges: the ranges depend on n and the chunk alone, each runs once, and with share
    // false every range runs on the calling thread.
    const std::ptrdiff_t n = 1000, chunk = 64;
    for (const bool share : {false, true}) {
        std::vector<std::pair<std::ptrdiff_t, std::ptrdiff_t>> seen(
            static_cast<size_t>((n + chunk - 1) / chunk));
        std::vector<std::thread::id> by(seen.size());
        std::vector<int> hits(static_cast<size_t>(n), 0);
        parallel_ranges(n, chunk, share, 4, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
            const size_t r = static_cast<size_t>(begin / chunk);
            seen[r] = {begin, end};
            by[r] = std::this_thread::get_id();
            for (std::ptrdiff_t i = begin; i < end; ++i) ++hits[static_cast<size_t>(i)];
        });
        for (size_t r = 0; r < seen.size(); ++r) {
            EXPECT_EQ(seen[r].first, static_cast<std::ptrdiff_t>(r) * chunk);
            EXPECT_EQ(seen[r].second, std::min(n, static_cast<std::ptrdiff_t>(r + 1) * chunk));
        }
        for (const int h : hits) EXPECT_EQ(h, 1);
        if (!share) {
            for (const auto& id : by) EXPECT_EQ(id, std::this_thread::get_id());
        }
    }
    int calls = 0;
    parallel_ranges(0, chunk, true, 4, [&](std::ptrdiff_t, std::ptrdiff_t) { ++calls; });
    EXPECT_EQ(calls, 0);
}
