// SPDX-License-Identifier: GPL-3.0-or-later
// Query latency against an indexed collection (collection_index.h) of 10^5 models: the target is
// at most 1 s per query on one core for the exact top 10. The collection's histograms are real
// ones repeated (as bench_600 does): the canonical forms of a few 10k-vertex meshes, their 66
// views and SIFT features, a codebook trained on a sample of them, one histogram set per mesh;
// model k of the index is mesh k mod M's. It measures the index build (seconds, bytes of
// histograms, resident memory before and after) and the latency of exact top-10 queries (each
// mesh as a query, several rounds) on 1 thread and on `--threads`. Prints one JSON line per stage.
//   canonform_bench_query MESH... [--models 100000] [--words 1500] [--rounds 3] [--threads 2]
#include "bench_util.h"
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/io/mesh_io.h"
#include "canonform/retrieval/collection_index.h"
#include "canonform/views/view_descriptor.h"

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace {

using canonform::bench::Clock;
using canonform::bench::median;
using canonform::bench::since;

/// CPU seconds of the calling thread (a 1-thread query runs on it: what the shared machine's load
/// does not inflate).
double thread_cpu() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Resident memory of this process (VmRSS), MiB.
double rss_mib() {
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace canonform;
    using namespace canonform::views;
    std::vector<std::string> meshes;
    long models = 100000;
    int words = 1500, rounds = 3, threads = 2;
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        if (a.rfind("--", 0) == 0 && k + 1 < argc) {
            const long v = std::atol(argv[++k]);
            if (a == "--models") models = v;
            else if (a == "--words") words = int(v);
            else if (a == "--rounds") rounds = int(v);
            else if (a == "--threads") threads = int(v);
            else { std::fprintf(stderr, "unknown option %s\n", a.c_str()); return 2; }
        } else {
            meshes.push_back(a);
        }
    }
    if (meshes.empty() || models < 1 || words < 1 || rounds < 1 || threads < 1) {
        std::fprintf(stderr, "usage: canonform_bench_query MESH... [--models 100000] [--words 1500] [--rounds 3] [--threads 2]\n");
        return 2;
    }
    // Real histograms: forms, views, SIFT, a codebook on a sample of the features.
    std::vector<ViewSet> sets;
    for (const auto& path : meshes) {
        const auto m = io::read_mesh(path);
        sets.push_back(compute_views(canonical::euclidean_canonical_form(m.V, m.F, {}).V, m.F));
    }
    std::vector<const std::vector<SiftDescriptors>*> all;
    for (const auto& s : sets) all.push_back(&s.features);
    const SiftDescriptors stacked = stack_features(all);
    CodebookOptions co;
    co.words = words;
    co.kmeans_iterations = 3;
    const auto t_cb = Clock::now();
    const Codebook cb = Codebook::train(stacked, co);
    std::printf("{\"stage\": \"codebook\", \"meshes\": %zu, \"descriptors\": %ld, \"words\": %d, \"wall_s\": %.2f}\n",
                meshes.size(), long(stacked.rows()), cb.size(), since(t_cb));
    std::vector<std::vector<Histogram>> real;
    double nnz = 0;
    for (const auto& s : sets) {
        real.push_back(view_histograms(s.features, cb));
        for (const auto& h : real.back()) nnz += double(h.size());
    }
    std::fflush(stdout);

    // The index of `models` models: real histograms repeated.
    std::vector<std::string> names(static_cast<std::size_t>(models)), classes(static_cast<std::size_t>(models));
    std::vector<std::vector<Histogram>> hist(static_cast<std::size_t>(models));
    for (long k = 0; k < models; ++k) {
        names[std::size_t(k)] = "m" + std::to_string(k);
        classes[std::size_t(k)] = "c" + std::to_string(k % long(real.size()));
        hist[std::size_t(k)] = real[std::size_t(k) % real.size()];
    }
    const double rss0 = rss_mib();
    const auto t_build = Clock::now();
    const retrieval::CollectionIndex x = retrieval::CollectionIndex::build(names, classes, hist, cb, "euclidean-N");
    const double build_s = since(t_build);
    hist.clear();
    hist.shrink_to_fit();
    std::printf("{\"stage\": \"index_build\", \"models\": %ld, \"mean_nonzeros_per_view\": %.1f, \"wall_s\": %.2f, "
                "\"index_mib\": %.1f, \"rss_before_mib\": %.0f, \"rss_after_mib\": %.0f}\n",
                models, nnz / double(real.size() * 66), build_s, double(x.bytes()) / (1 << 20), rss0, rss_mib());
    std::fflush(stdout);

    // Exact top-10 queries: every real mesh as a query, `rounds` times; 1 thread, then `threads`.
    for (int t : {1, threads}) {
        std::vector<double> lat, cpu;
        for (int r = 0; r < rounds; ++r)
            for (const auto& q : real) {
                const auto t0 = Clock::now();
                const double c0 = thread_cpu();
                const auto top = x.top(q, 10, t);
                lat.push_back(since(t0));
                cpu.push_back(thread_cpu() - c0);
                if (top.size() != std::size_t(std::min<long>(10, models)) || top[0].distance != 0.f) {
                    std::fprintf(stderr, "wrong answer: the query itself is not first\n");
                    return 1;
                }
            }
        std::printf("{\"stage\": \"query_top10\", \"models\": %ld, \"threads\": %d, \"queries\": %zu, \"median_s\": %.3f, "
                    "\"min_s\": %.3f, \"max_s\": %.3f, \"median_calling_thread_cpu_s\": %.3f}\n",
                    models, t, lat.size(), median(lat), *std::min_element(lat.begin(), lat.end()),
                    *std::max_element(lat.begin(), lat.end()), median(cpu));
        std::fflush(stdout);
        if (threads == 1) break;
    }
    return 0;
}
