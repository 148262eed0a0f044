// SPDX-License-Identifier: GPL-3.0-or-later
// Queries against an indexed collection (collection_index.h): the two-stage query (first pass +
// exact clock matching of the candidates) next to the exhaustive one - recall@10 against the
// exact top 10, latency on one core, index memory and build time. Prints one JSON line per stage.
//
//   canonform_bench_query synthetic REAL [--models 100000] [--queries 1000] [--candidates 250,500,...]
//       [--latency-queries 20] [--latency-candidates 1000,2000] [--threads 2] [--truth FILE]
//       [--truth-budget S] [--first-query F] [--save DIR] [--noise 0.1,0.5]
//       [--dims 128] [--no-orbits] [--no-sqrt] [--seed 1]
//   canonform_bench_query collection METHOD_FOLDER... [--candidates 10,20,...] [--dims 128] [--no-orbits]
//   [--no-sqrt] canonform_bench_query noise REAL [--candidates 30,50,70 (noise levels in %)]
//   canonform_bench_query rerank INDEX_FILE [--queries 20] [--threads 2] [--dump FILE]
//
// synthetic: an index of --models models made from the real histograms of REAL (a method folder
// of a retrieval run: models.csv, descriptors/, codebook.bin) with noise, so that no model is a
// copy and no cluster is trivially apart: model k takes a random real model (its base) and
// another (its donor); each keypoint of the base is kept with probability 1 - p (p uniform in
// --noise, per model), else it moves to one of the 8 codebook words nearest to its own (in SIFT
// space) or is replaced by a keypoint drawn from the donor's same view (half and half); then the
// views are permuted by a random one of the 24 cube rotations. Models fill the space between the
// real ones instead of clustering around them (`noise` mode: the distances this gives). The queries
// are --queries further such models (not in the index; --first-query F skips the first F). Their exact top 10
// (exhaustive, --threads threads; cached in --truth) is the reference for the recall of the two-stage query
// at each candidate count. Latency: --latency-queries of them on one thread, exhaustive and two-stage
// alternating, medians of wall and thread CPU seconds (--latency-candidates: two-stage at each count, with
// the first pass and the rerank timed apart). --truth keeps the exact answers for later runs; --truth-budget
// bounds the seconds spent computing them (the recall then says over how many). With
// --save the index is written there, freed, and read back: the memory of the loaded index is measured on its
// own. collection: the index of each real method folder; every member is a query; recall@10 against the
// exhaustive top 10 at each candidate count (the first pass forced on by the count).
#include "bench_util.h"
#include "canonform/common/heap_pages.h"
#include "canonform/common/parallel.h"
#include "canonform/io/csv.h"
#include "canonform/io/files.h"
#include "canonform/retrieval/collection_index.h"
#include "canonform/views/bag_of_features.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_directions.h"

#include <fcntl.h>
#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace canonform;
using canonform::bench::Clock;
using canonform::bench::median;
using canonform::bench::since;
using views::Histogram;

double thread_cpu() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double process_cpu() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Resident memory of this process (VmRSS; RssAnon: private; RssFile: mapped file pages), MiB.
double rss_mib(const char* field = "VmRSS:") {
    std::ifstream in("/proc/self/status");
    const std::size_t n = std::strlen(field);
    for (std::string line; std::getline(in, line);)
        if (line.compare(0, n, field) == 0) return std::atof(line.c_str() + n) / 1024.0;
    return 0;
}

/// Drops the file's pages from the page cache (no other mapping of it may be alive).
void evict(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return;
    ::fdatasync(fd);
    ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
    ::close(fd);
}

std::vector<std::size_t> parse_list(const std::string& s) {
    std::vector<std::size_t> out;
    std::size_t at = 0;
    while (at < s.size()) {
        const std::size_t comma = s.find(',', at);
        out.push_back(std::stoul(s.substr(at, comma == std::string::npos ? std::string::npos : comma - at)));
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    return out;
}

/// The real collection: histograms, classes and codebook of a method folder.
struct Real {
    std::vector<std::string> names, classes;
    std::vector<std::vector<Histogram>> models;
    views::Codebook codebook;
};

Real read_real(const std::string& folder) {
    Real r;
    const auto rows = io::read_csv(folder + "/models.csv");
    for (std::size_t k = 1; k < rows.size(); ++k) {
        r.names.push_back(rows[k][0]);
        r.classes.push_back(rows[k][1]);
        r.models.push_back(
            views::read_descriptor(folder + "/descriptors/" + rows[k][0] + ".cfvd").histograms);
    }
    r.codebook = views::Codebook::load(folder + "/codebook.bin");
    return r;
}

/// Changed whenever Synthetic::model() gives other models: the key of the cached exact answers.
constexpr std::uint64_t kGeneratorVersion = 2;

/// The synthetic collection of the header.
struct Synthetic {
    const Real& real;
    std::vector<std::vector<int>> near;  // 8 nearest words of each word
    std::vector<std::vector<int>> maps;
    double lo, hi;
    std::uint64_t seed;

    Synthetic(const Real& r, double lo_, double hi_, std::uint64_t seed_)
        : real(r), maps(views::rotation_view_maps()), lo(lo_), hi(hi_), seed(seed_) {
        const auto& W = r.codebook.words();
        const int n = r.codebook.size();
        near.resize(static_cast<std::size_t>(n));
        for (int a = 0; a < n; ++a) {
            std::vector<std::pair<double, int>> d;
            for (int b = 0; b < n; ++b)
                if (b != a) d.emplace_back((W.row(a) - W.row(b)).squaredNorm(), b);
            std::partial_sort(d.begin(), d.begin() + 8, d.end());
            for (int k = 0; k < 8; ++k)
                near[static_cast<std::size_t>(a)].push_back(d[static_cast<std::size_t>(k)].second);
        }
    }

    /// Model k (and its base).
    std::vector<Histogram> model(std::uint64_t k, std::size_t* base = nullptr) const {
        std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + k);
        auto u01 = [&] { return static_cast<double>(g() >> 11) * 0x1.0p-53; };
        const std::size_t R = real.models.size();
        const std::size_t b = g() % R;
        const std::size_t d = (b + 1 + g() % (R - 1)) % R;  // the donor: another real model
        const std::size_t rot = g() % maps.size();
        const double p = lo + (hi - lo) * u01();
        if (base) *base = b;
        const auto& src = real.models[b];
        const auto& donor = real.models[d];
        std::vector<Histogram> out(src.size());
        std::vector<int> words, pool;
        for (std::size_t i = 0; i < src.size(); ++i) {
            words.clear();
            pool.clear();
            for (const auto& [w, c] : donor[i])
                for (int t = 0; t < static_cast<int>(c); ++t) pool.push_back(w);
            for (const auto& [w, c] : src[i])
                for (int t = 0; t < static_cast<int>(c); ++t) {
                    const double u = u01();
                    if (u >= p) {
                        words.push_back(w);  // kept
                    } else if (u < p / 2) {
                        const auto& nb = near[static_cast<std::size_t>(w)];
                        words.push_back(nb[g() % nb.size()]);  // moved to a neighbouring word
                    } else if (!pool.empty()) {
                        words.push_back(pool[g() % pool.size()]);  // the donor's view instead
                    }
                }
            out[static_cast<std::size_t>(maps[rot][i])] = views::histogram(words);
        }
        return out;
    }
};

/// A method folder named by its run and method (RUN/METHOD), not by where it is.
std::string short_name(const std::string& folder) {
    const std::filesystem::path p = std::filesystem::path(folder).lexically_normal();
    const std::filesystem::path f = p.has_filename() ? p : p.parent_path();
    return (f.parent_path().filename() / f.filename()).string();
}

double recall_at(const std::vector<retrieval::IndexMatch>& got,
                 const std::vector<retrieval::IndexMatch>& truth) {
    std::set<std::size_t> t;
    for (const auto& m : truth) t.insert(m.model);
    std::size_t hit = 0;
    for (const auto& m : got) hit += t.count(m.model);
    return truth.empty() ? 1.0 : double(hit) / double(truth.size());
}

struct Args {
    std::string mode;
    std::vector<std::string> inputs;
    long models = 100000, queries = 1000, latency_queries = 20;
    double truth_budget = 0;
    long first_query = 0;
    int threads = 2;
    std::string truth, save, candidates, latency_candidates, dump;
    double lo = 0.1, hi = 0.5;
    std::uint64_t seed = 1;
    retrieval::SummaryOptions summary;
};

int collection(const Args& a) {
    const std::vector<std::size_t> cands =
        parse_list(a.candidates.empty() ? "10,15,20,30,50,100" : a.candidates);
    for (const std::string& folder : a.inputs) {
        const Real r = read_real(folder);
        retrieval::CollectionIndex::Builder b(r.codebook, "euclidean-N", 0,
                                              static_cast<int>(r.models[0].size()));
        for (std::size_t k = 0; k < r.models.size(); ++k) b.add(r.names[k], r.classes[k], r.models[k]);
        const retrieval::CollectionIndex x = b.finish(&a.summary, a.threads);
        std::vector<std::vector<retrieval::IndexMatch>> truth;
        for (const auto& q : r.models) truth.push_back(x.top(q, 10, a.threads));
        for (std::size_t c : cands) {
            if (c >= x.size()) continue;
            double sum = 0, worst = 1;
            for (std::size_t k = 0; k < r.models.size(); ++k) {
                retrieval::SearchOptions o;
                o.candidates = c;
                o.threads = a.threads;
                const double rc = recall_at(x.search(r.models[k], 10, o), truth[k]);
                sum += rc;
                worst = std::min(worst, rc);
            }
            std::printf(
                "{\"stage\": \"recall\", \"collection\": \"%s\", \"models\": %zu, \"queries\": %zu, "
                "\"candidates\": %zu, "
                "\"dims\": %d, \"orbits\": %d, \"sqrt\": %d, \"recall_at_10\": %.4f, \"worst_query\": "
                "%.2f}\n",
                short_name(folder).c_str(), x.size(), r.models.size(), c, a.summary.dims,
                int(a.summary.orbits), int(a.summary.sqrt_counts), sum / double(r.models.size()), worst);
            std::fflush(stdout);
        }
    }
    return 0;
}

/// How far noise moves a model: for each noise level, the median clock-matching distance between
/// two noisy copies of one real model (siblings) and between a copy and its real model, next to
/// the real collection's median nearest-neighbour and same-class distances.
int noise(const Args& a) {
    const Real real = read_real(a.inputs.at(0));
    const auto maps = views::rotation_view_maps();
    {
        const Eigen::MatrixXf D = views::distance_matrix(real.models, maps, a.threads);
        std::vector<double> nn, same;
        for (Eigen::Index i = 0; i < D.rows(); ++i) {
            double best = 1e30;
            for (Eigen::Index j = 0; j < D.cols(); ++j)
                if (j != i) {
                    best = std::min(best, double(D(i, j)));
                    if (real.classes[std::size_t(i)] == real.classes[std::size_t(j)]) same.push_back(D(i, j));
                }
            nn.push_back(best);
        }
        std::printf(
            "{\"stage\": \"noise\", \"real_models\": %zu, \"median_real_nn\": %.2f, "
            "\"median_real_same_class\": %.2f}\n",
            real.models.size(), median(nn), median(same));
    }
    for (std::size_t level : parse_list(a.candidates.empty() ? "10,30,50,60,70,80" : a.candidates)) {
        const double p = double(level) / 100.0;
        const Synthetic syn(real, p, p, a.seed);
        std::vector<double> sib, base;
        for (std::uint64_t k = 0; k < 200; ++k) {
            std::size_t b1 = 0;
            const auto m1 = syn.model(2 * k, &b1);
            // A sibling: the same base, drawn until one is found (bases are uniform).
            for (std::uint64_t t = 1000000 + k * 10000;; ++t) {
                std::size_t b2 = 0;
                const auto m2 = syn.model(t, &b2);
                if (b2 != b1) continue;
                sib.push_back(views::clock_matching_distance(m1, m2, maps));
                break;
            }
            base.push_back(views::clock_matching_distance(m1, real.models[b1], maps));
        }
        std::printf(
            "{\"stage\": \"noise\", \"p\": %.2f, \"median_sibling_distance\": %.2f, "
            "\"median_distance_to_base\": %.2f}\n",
            p, median(sib), median(base));
        std::fflush(stdout);
    }
    return 0;
}

int synthetic(const Args& a) {
    const Real real = read_real(a.inputs.at(0));
    const Synthetic syn(real, a.lo, a.hi, a.seed);
    const std::size_t N = static_cast<std::size_t>(a.models);
    std::printf("{\"stage\": \"real\", \"folder\": \"%s\", \"models\": %zu, \"words\": %d}\n",
                short_name(a.inputs[0]).c_str(), real.models.size(), real.codebook.size());
    std::fflush(stdout);

    // The index: models generated in parallel chunks, added in order.
    const double rss0 = rss_mib();
    retrieval::CollectionIndex::Builder builder(real.codebook, "euclidean-N", 0, views::kNumViews);
    double generate_s = 0, add_s = 0;
    {
        const std::size_t chunk = 8192;
        std::vector<std::vector<Histogram>> buf(chunk);
        for (std::size_t begin = 0; begin < N; begin += chunk) {
            const std::size_t end = std::min(N, begin + chunk);
            const auto t0 = Clock::now();
            ParallelOptions par;
            par.threads = a.threads;
            parallel_for(
                static_cast<std::ptrdiff_t>(end - begin),
                [&](std::ptrdiff_t k, int) {
                    buf[static_cast<std::size_t>(k)] = syn.model(begin + static_cast<std::size_t>(k));
                },
                par);
            generate_s += since(t0);
            const auto t1 = Clock::now();
            for (std::size_t k = begin; k < end; ++k)
                builder.add("s" + std::to_string(k), real.classes[0], buf[k - begin]);
            add_s += since(t1);
        }
    }
    const double rss_encoded = rss_mib();
    const auto t_fin = Clock::now();
    const double c_fin = process_cpu();
    retrieval::CollectionIndex x = builder.finish(&a.summary, a.threads);
    const double finish_s = since(t_fin), finish_cpu = process_cpu() - c_fin;
    std::printf(
        "{\"stage\": \"index_build\", \"models\": %zu, \"threads\": %d, \"generate_s\": %.1f, \"encode_s\": "
        "%.1f, "
        "\"first_pass_s\": %.1f, \"first_pass_cpu_s\": %.1f, \"histogram_mib\": %.1f, \"codes_mib\": %.1f, "
        "\"dims\": %d, \"orbits\": %d, \"sqrt\": %d, \"rss_before_mib\": %.0f, \"rss_encoded_mib\": %.0f, "
        "\"rss_after_mib\": %.0f}\n",
        N, a.threads, generate_s, add_s, finish_s, finish_cpu, double(x.bytes()) / (1 << 20),
        double(x.first_pass().bytes()) / (1 << 20), a.summary.dims, int(a.summary.orbits),
        int(a.summary.sqrt_counts), rss0, rss_encoded, rss_mib());
    std::fflush(stdout);
    {
        // How far the histograms' byte code is from the order-0 entropy of what it codes - word
        // gaps, counts and entries per view, each symbol on its own - over a sample of models: a
        // lower bound for any code that takes these symbols one at a time independently.
        std::map<int, double> gaps, counts, entries;
        double symbols = 0, views = 0;
        const std::size_t S = std::min<std::size_t>(N, 20000);
        for (std::size_t k = 0; k < S; ++k)
            for (const Histogram& h : x.histograms(k * N / S)) {
                entries[static_cast<int>(h.size())] += 1;
                views += 1;
                int prev = -1;
                for (const auto& [w, c] : h) {
                    gaps[w - prev] += 1;
                    counts[static_cast<int>(c)] += 1;
                    symbols += 1;
                    prev = w;
                }
            }
        auto bits = [](const std::map<int, double>& f, double total) {
            double b = 0;
            for (const auto& [v, n] : f) b -= n * std::log2(n / total);
            return b;
        };
        const double bound =
            (bits(gaps, symbols) + bits(counts, symbols) + bits(entries, views)) / 8 / double(S);
        const double coded = double(x.bytes() - (N + 1) * sizeof(std::uint64_t)) / double(N);
        std::printf(
            "{\"stage\": \"histogram_entropy\", \"sample\": %zu, \"nonzeros_per_model\": %.0f, "
            "\"coded_bytes_per_model\": %.0f, \"order0_entropy_bytes_per_model\": %.0f, "
            "\"order0_histogram_mib\": %.1f}\n",
            S, symbols / double(S), coded, bound, bound * double(N) / (1 << 20));
        std::fflush(stdout);
    }
    if (!a.save.empty()) {
        io::make_directories(a.save);
        const std::string path = a.save + "/index.cfci";
        const auto t0 = Clock::now();
        x.save(path);
        const double save_s = since(t0);
        x = retrieval::CollectionIndex();
        malloc_trim(0);
        evict(path);
        const double before = rss_mib(), anon0 = rss_mib("RssAnon:");
        const auto t1 = Clock::now();
        x = retrieval::CollectionIndex::load(path, true);
        const double load_s = since(t1);
        std::printf(
            "{\"stage\": \"index_file\", \"models\": %zu, \"file_mib\": %.1f, \"save_s\": %.1f, "
            "\"mapped_load_s\": %.1f, "
            "\"rss_before_load_mib\": %.0f, \"rss_after_load_mib\": %.0f, \"private_index_mib\": %.0f, "
            "\"mapped_file_pages_mib\": %.0f}\n",
            N, double(std::filesystem::file_size(path)) / (1 << 20), save_s, load_s, before, rss_mib(),
            rss_mib("RssAnon:") - anon0, rss_mib("RssFile:"));
        std::fflush(stdout);
    }

    // The queries and their exact top 10 (cached).
    const std::size_t Q = static_cast<std::size_t>(a.queries);
    std::vector<std::vector<Histogram>> queries(Q);
    std::vector<std::size_t> bases(Q);
    const std::size_t F = static_cast<std::size_t>(a.first_query);
    for (std::size_t q = 0; q < Q; ++q) queries[q] = syn.model(N + 1000000000ULL + F + q, &bases[q]);
    // Their exact top 10, cached in --truth: the file holds the answers of the first queries, in
    // order (a header: models, queries held, seed, noise); a run computes the missing ones in
    // chunks and rewrites the file after each, so an interrupted or budgeted run goes on later.
    // With --truth-budget S no chunk starts after S seconds: the recall is over the queries
    // whose exact answers are known, and says how many.
    std::vector<std::vector<retrieval::IndexMatch>> truth(Q);
    // The key: noise range, the generator's version and the first query (answers computed for
    // another generator or other queries are not taken).
    const std::uint64_t noise_key =
        (std::uint64_t(a.lo * 1e6) * 1000003ULL + std::uint64_t(a.hi * 1e6)) * 31ULL + kGeneratorVersion +
        1000ULL * F;
    std::size_t known = 0;
    if (!a.truth.empty() && io::is_file(a.truth)) {
        std::ifstream in(a.truth, std::ios::binary);
        std::uint64_t head[4];
        in.read(reinterpret_cast<char*>(head), sizeof head);
        if (in && head[0] == N && head[2] == a.seed && head[3] == noise_key) {
            const std::size_t held = std::min<std::size_t>(Q, head[1]);
            for (std::size_t q = 0; q < held; ++q) {
                for (int r = 0; r < 10; ++r) {
                    std::uint32_t m;
                    float d;
                    in.read(reinterpret_cast<char*>(&m), 4);
                    in.read(reinterpret_cast<char*>(&d), 4);
                    if (!in || m >= N) break;
                    truth[q].push_back({m, x.names()[m], x.classes()[m], d});
                }
                if (truth[q].size() != 10) {
                    truth[q].clear();
                    break;
                }
                known = q + 1;
            }
        }
    }
    {
        const std::size_t from = known;
        const auto t0 = Clock::now();
        const double c0 = process_cpu();
        const std::size_t chunk = 10;
        while (known < Q && (a.truth_budget <= 0 || since(t0) < a.truth_budget)) {
            const std::size_t end = std::min(Q, known + chunk);
            for (std::size_t q = known; q < end; ++q) truth[q] = x.top(queries[q], 10, a.threads);
            known = end;
            if (!a.truth.empty()) {
                std::string b;
                const std::uint64_t head[4] = {N, known, a.seed, noise_key};
                b.append(reinterpret_cast<const char*>(head), sizeof head);
                for (std::size_t q = 0; q < known; ++q)
                    for (const auto& m : truth[q]) {
                        const auto mm = static_cast<std::uint32_t>(m.model);
                        b.append(reinterpret_cast<const char*>(&mm), 4);
                        b.append(reinterpret_cast<const char*>(&m.distance), 4);
                    }
                io::write_file_atomic(a.truth, b);
            }
        }
        std::printf(
            "{\"stage\": \"truth\", \"queries\": %zu, \"cached\": %zu, \"computed\": %zu, \"threads\": %d, "
            "\"wall_s\": %.1f, \"cpu_s\": %.1f}\n",
            known, from, known - from, a.threads, since(t0), process_cpu() - c0);
        std::fflush(stdout);
        if (known == 0) return 1;
    }
    // How hard the queries are: the exact distances of ranks 1, 10 and 11, the margin between
    // ranks 10 and 11, and how many of the top 10 share the query's base.
    {
        std::vector<double> d1, d10, margin, same;
        for (std::size_t q = 0; q < std::min<std::size_t>(known, 20); ++q) {
            const auto t11 = x.top(queries[q], 11, a.threads);
            d1.push_back(t11[0].distance);
            d10.push_back(t11[9].distance);
            margin.push_back(t11[10].distance - t11[9].distance);
            std::size_t s = 0;
            for (std::size_t r = 0; r < 10; ++r) {
                std::size_t b = 0;
                syn.model(t11[r].model, &b);
                s += b == bases[q];
            }
            same.push_back(double(s));
        }
        std::printf(
            "{\"stage\": \"difficulty\", \"queries\": %zu, \"median_d1\": %.3f, \"median_d10\": %.3f, "
            "\"median_margin_10_11\": %.4f, \"median_top10_same_base\": %.1f}\n",
            d1.size(), median(d1), median(d10), median(margin), median(same));
        std::fflush(stdout);
    }
    // Recall against the candidate count.
    const std::vector<std::size_t> cands =
        parse_list(a.candidates.empty() ? "250,500,1000,2000,4000" : a.candidates);
    for (std::size_t c : cands) {
        double sum = 0, worst = 1;
        std::size_t perfect = 0;
        for (std::size_t q = 0; q < known; ++q) {
            retrieval::SearchOptions o;
            o.candidates = c;
            o.threads = a.threads;
            const double r = recall_at(x.search(queries[q], 10, o), truth[q]);
            sum += r;
            worst = std::min(worst, r);
            perfect += r == 1.0;
        }
        std::printf(
            "{\"stage\": \"recall\", \"models\": %zu, \"queries\": %zu, \"candidates\": %zu, "
            "\"recall_at_10\": %.4f, "
            "\"queries_all_10\": %.4f, \"worst_query\": %.2f}\n",
            N, known, c, sum / double(known), double(perfect) / double(known), worst);
        std::fflush(stdout);
    }
    // Latency on one thread: exhaustive and two-stage (default candidates) alternating.
    {
        std::vector<double> ew, ec, tw, tc, fw;
        const std::size_t L = std::min<std::size_t>(Q, static_cast<std::size_t>(a.latency_queries));
        retrieval::SearchOptions two;
        two.threads = 1;
        two.candidates = x.default_candidates(10);
        retrieval::SearchOptions ex;
        ex.exact = true;
        ex.threads = 1;
        for (std::size_t q = 0; q < L; ++q)
            for (int turn = 0; turn < 2; ++turn) {
                const bool exact = (turn == 0) == (q % 2 == 0);
                const auto t0 = Clock::now();
                const double c0 = thread_cpu();
                const auto got = x.search(queries[q], 10, exact ? ex : two);
                const double w = since(t0), c = thread_cpu() - c0;
                (exact ? ew : tw).push_back(w);
                (exact ? ec : tc).push_back(c);
                if (got.size() != 10) return 1;
            }
        for (std::size_t q = 0; q < L; ++q) {  // the first pass alone
            const auto t0 = Clock::now();
            const auto code = x.code(queries[q]);
            const auto c = x.first_pass().nearest(code.data(), two.candidates, 1);
            fw.push_back(since(t0));
        }
        std::printf(
            "{\"stage\": \"latency\", \"models\": %zu, \"threads\": 1, \"queries\": %zu, \"candidates\": "
            "%zu, "
            "\"mapped\": %d, \"rss_mib\": %.0f, \"private_mib\": %.0f, \"mapped_file_pages_mib\": %.0f, "
            "\"exact_median_s\": %.4f, \"exact_median_cpu_s\": %.4f, \"two_stage_median_s\": %.4f, "
            "\"two_stage_median_cpu_s\": %.4f, \"first_pass_median_s\": %.4f, \"speedup_cpu\": %.1f}\n",
            N, L, two.candidates, int(x.mapped()), rss_mib(), rss_mib("RssAnon:"), rss_mib("RssFile:"),
            median(ew), median(ec), median(tw), median(tc), median(fw),
            median(ec) / std::max(1e-9, median(tc)));
        std::fflush(stdout);
    }
    // Two-stage latency per candidate count (--latency-candidates): the counts in turn, their order
    // reversed every other query; the first pass timed apart as well: the rerank is the query less
    // its first pass (clock matching that gives up the candidates found farther than the kept
    // ones); every_candidate: clock matching of every candidate to the end (distances()).
    if (!a.latency_candidates.empty()) {
        const std::vector<std::size_t> counts = parse_list(a.latency_candidates);
        const std::size_t L = std::min<std::size_t>(Q, static_cast<std::size_t>(a.latency_queries));
        std::vector<std::vector<double>> tw(counts.size()), tc(counts.size()), fc(counts.size()),
            rc(counts.size()), ac(counts.size());
        for (std::size_t q = 0; q < L; ++q)
            for (std::size_t t = 0; t < counts.size(); ++t) {
                const std::size_t i = q % 2 == 0 ? t : counts.size() - 1 - t;
                retrieval::SearchOptions two;
                two.threads = 1;
                two.candidates = counts[i];
                const auto t0 = Clock::now();
                const double c0 = thread_cpu();
                const auto got = x.search(queries[q], 10, two);
                tw[i].push_back(since(t0));
                tc[i].push_back(thread_cpu() - c0);
                if (got.size() != 10) return 1;
                const double c1 = thread_cpu();
                const auto code = x.code(queries[q]);
                const auto cand = x.first_pass().nearest(code.data(), counts[i], 1);
                const double c2 = thread_cpu();
                const auto d = x.distances(queries[q], cand, 1);
                ac[i].push_back(thread_cpu() - c2);
                fc[i].push_back(c2 - c1);
                rc[i].push_back(std::max(0.0, tc[i].back() - (c2 - c1)));
            }
        for (std::size_t i = 0; i < counts.size(); ++i) {
            std::printf(
                "{\"stage\": \"latency_by_candidates\", \"models\": %zu, \"threads\": 1, \"queries\": %zu, "
                "\"candidates\": %zu, \"two_stage_median_s\": %.4f, \"two_stage_median_cpu_s\": %.4f, "
                "\"first_pass_median_cpu_s\": %.4f, \"rerank_median_cpu_s\": %.4f, "
                "\"rerank_cpu_us_per_candidate\": %.3f, \"every_candidate_cpu_us\": %.3f}\n",
                N, L, counts[i], median(tw[i]), median(tc[i]), median(fc[i]), median(rc[i]),
                1e6 * median(rc[i]) / double(counts[i]), 1e6 * median(ac[i]) / double(counts[i]));
            std::fflush(stdout);
        }
    }
    // Two-stage latency with the histograms' pages out of the page cache (a mapped index just
    // loaded: each query reads its candidates from the disk).
    if (!a.save.empty()) {
        const std::string path = a.save + "/index.cfci";
        std::vector<double> w, c;
        const std::size_t L = std::min<std::size_t>(Q, static_cast<std::size_t>(a.latency_queries));
        for (std::size_t q = 0; q < L; ++q) {
            x = retrieval::CollectionIndex();
            evict(path);
            x = retrieval::CollectionIndex::load(path, true);
            retrieval::SearchOptions two;
            two.threads = 1;
            two.candidates = x.default_candidates(10);
            const auto t0 = Clock::now();
            const double c0 = thread_cpu();
            x.search(queries[q], 10, two);
            w.push_back(since(t0));
            c.push_back(thread_cpu() - c0);
        }
        std::printf(
            "{\"stage\": \"latency_cold\", \"models\": %zu, \"threads\": 1, \"queries\": %zu, "
            "\"candidates\": %zu, "
            "\"two_stage_median_s\": %.4f, \"two_stage_median_cpu_s\": %.4f}\n",
            N, L, x.default_candidates(10), median(w), median(c));
        std::fflush(stdout);
    }
    return 0;
}

/// Clock matching alone over a saved index (rerank INDEX_FILE): --queries members (evenly spaced)
/// as queries against every model on one thread, without and with `self`; CPU microseconds per
/// model, medians. With --dump FILE every distance is written (per query: N floats without, then
/// N with `self`), to compare two builds bit for bit; --threads T checks that T threads give the
/// same floats.
int rerank(const Args& a) {
    const retrieval::CollectionIndex x = retrieval::CollectionIndex::load(a.inputs.at(0), false);
    const std::size_t N = x.size(), Q = std::min<std::size_t>(N, static_cast<std::size_t>(a.queries));
    std::vector<double> plain, own;
    std::string out;
    bool threads_equal = true;
    for (std::size_t k = 0; k < Q; ++k) {
        const std::size_t m = k * N / Q;
        const auto h = x.histograms(m);
        double c0 = thread_cpu();
        const std::vector<float> d = x.distances(h, 1);
        plain.push_back(1e6 * (thread_cpu() - c0) / double(N));
        c0 = thread_cpu();
        const std::vector<float> e = x.distances(h, 1, static_cast<std::ptrdiff_t>(m));
        own.push_back(1e6 * (thread_cpu() - c0) / double(N));
        if (a.threads != 1)
            threads_equal = threads_equal && x.distances(h, a.threads) == d &&
                            x.distances(h, a.threads, static_cast<std::ptrdiff_t>(m)) == e;
        if (!a.dump.empty()) {
            out.append(reinterpret_cast<const char*>(d.data()), d.size() * sizeof(float));
            out.append(reinterpret_cast<const char*>(e.data()), e.size() * sizeof(float));
        }
    }
    if (!a.dump.empty()) io::write_file_atomic(a.dump, out);
    std::printf(
        "{\"stage\": \"rerank\", \"models\": %zu, \"queries\": %zu, \"threads\": 1, "
        "\"cpu_us_per_model_median\": %.3f, \"self_cpu_us_per_model_median\": %.3f, \"threads_checked\": %d, "
        "\"threads_equal\": %s}\n",
        N, Q, median(plain), median(own), a.threads, threads_equal ? "true" : "false");
    std::fflush(stdout);
    return threads_equal ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    canonform::advise_heap_huge_pages();  // as the tool does (common/heap_pages.h)
    Args a;
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: canonform_bench_query synthetic REAL_METHOD_FOLDER [options] | collection "
                     "FOLDER... [options]\n");
        return 2;
    }
    a.mode = argv[1];
    for (int k = 2; k < argc; ++k) {
        const std::string o = argv[k];
        auto value = [&]() -> std::string {
            if (k + 1 >= argc) throw std::runtime_error("missing value of " + o);
            return argv[++k];
        };
        if (o == "--models")
            a.models = std::stol(value());
        else if (o == "--queries")
            a.queries = std::stol(value());
        else if (o == "--latency-candidates")
            a.latency_candidates = value();
        else if (o == "--dump")
            a.dump = value();
        else if (o == "--latency-queries")
            a.latency_queries = std::stol(value());
        else if (o == "--threads")
            a.threads = std::stoi(value());
        else if (o == "--truth")
            a.truth = value();
        else if (o == "--truth-budget")
            a.truth_budget = std::stod(value());
        else if (o == "--first-query")
            a.first_query = std::stol(value());
        else if (o == "--save")
            a.save = value();
        else if (o == "--candidates")
            a.candidates = value();
        else if (o == "--seed")
            a.seed = std::stoull(value());
        else if (o == "--dims")
            a.summary.dims = std::stoi(value());
        else if (o == "--sample")
            a.summary.sample = std::stoi(value());
        else if (o == "--no-orbits")
            a.summary.orbits = false;
        else if (o == "--no-sqrt")
            a.summary.sqrt_counts = false;
        else if (o == "--noise") {
            const std::string v = value();
            a.lo = std::stod(v.substr(0, v.find(',')));
            a.hi = std::stod(v.substr(v.find(',') + 1));
        } else if (o.rfind("--", 0) == 0) {
            std::fprintf(stderr, "unknown option %s\n", o.c_str());
            return 2;
        } else {
            a.inputs.push_back(o);
        }
    }
    if (a.inputs.empty() || a.models < 1 || a.queries < 1) return 2;
    if (a.mode == "synthetic") return synthetic(a);
    if (a.mode == "collection") return collection(a);
    if (a.mode == "noise") return noise(a);
    if (a.mode == "rerank") return rerank(a);
    std::fprintf(stderr, "unknown mode %s\n", a.mode.c_str());
    return 2;
}
