// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/collection_index.h"

#include "canonform/common/parallel.h"
#include "canonform/io/csv.h"
#include "canonform/io/files.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_directions.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>

namespace canonform::retrieval {

namespace {

constexpr int kLanes = 80;  // query views per word, padded to a multiple of 16 (>= 66 views)

/// The distinct (query view i, model view j) pairs the rotations use, in the order of
/// bag_of_features.cpp's plan (i ascending, j ascending), and per view i and rotation r the pair's index.
struct Plan {
    std::vector<int> pi, pj;
    std::vector<int> pair_of;  // V x R: pair_of[i * R + r]
    int rotations = 0;
};

Plan make_plan(const std::vector<std::vector<int>>& maps, int views) {
    Plan p;
    p.rotations = static_cast<int>(maps.size());
    p.pair_of.resize(static_cast<std::size_t>(views) * maps.size());
    for (int i = 0; i < views; ++i) {
        std::vector<int> partners;
        for (const auto& m : maps) partners.push_back(m[static_cast<std::size_t>(i)]);
        std::sort(partners.begin(), partners.end());
        partners.erase(std::unique(partners.begin(), partners.end()), partners.end());
        const int base = static_cast<int>(p.pi.size());
        for (int j : partners) {
            p.pi.push_back(i);
            p.pj.push_back(j);
        }
        for (std::size_t r = 0; r < maps.size(); ++r)
            p.pair_of[static_cast<std::size_t>(i) * maps.size() + r] =
                base + static_cast<int>(std::lower_bound(partners.begin(), partners.end(), maps[r][static_cast<std::size_t>(i)]) -
                                        partners.begin());
    }
    return p;
}

/// bag_of_features.cpp's view distance from the intersection and the two sums.
inline double distance_from(double inter, double sa, double sb) {
    if (sa <= 0 && sb <= 0) return 0.0;
    const double m = std::max(sa, sb);
    return std::clamp(1.0 - inter / m, 0.0, 1.0);
}

struct Scratch {
    std::vector<std::uint16_t> acc;  // V x kLanes
    std::vector<double> msum, pair, rot;
};

/// 16 lanes of 16-bit counts (one AVX2 register; two SSE2 ones in the default build).
typedef std::uint16_t Lanes __attribute__((vector_size(32)));
static_assert(kLanes == 5 * 16, "five registers of lanes");

/// Accumulates, for model view j, the intersections with every query view (lanes) - the hot loop:
/// per entry (word w, count c) acc += min(query counts of w, c), in registers.
#if defined(_WIN32)  // no ifunc for target_clones, and no 32-byte stack alignment for AVX (codebook.cpp)
#define CANONFORM_INDEX_CLONES
#else
#define CANONFORM_INDEX_CLONES __attribute__((target_clones("avx2", "default")))
#endif
CANONFORM_INDEX_CLONES void accumulate(const std::uint16_t* entries, std::uint64_t begin,
                                                                   std::uint64_t end, const std::uint16_t* qt,
                                                                   std::uint16_t* acc, double* sum) {
    Lanes a0 = {}, a1 = {}, a2 = {}, a3 = {}, a4 = {};
    std::uint32_t s = 0;
    for (std::uint64_t e = begin; e < end; ++e) {
        const std::uint16_t c = entries[2 * e + 1];
        const std::uint16_t* q = qt + static_cast<std::size_t>(entries[2 * e]) * kLanes;
        s += c;
        const Lanes cv = Lanes{} + c;
        Lanes q0, q1, q2, q3, q4;
        std::memcpy(&q0, q, 32);
        std::memcpy(&q1, q + 16, 32);
        std::memcpy(&q2, q + 32, 32);
        std::memcpy(&q3, q + 48, 32);
        std::memcpy(&q4, q + 64, 32);
        a0 += q0 < cv ? q0 : cv;
        a1 += q1 < cv ? q1 : cv;
        a2 += q2 < cv ? q2 : cv;
        a3 += q3 < cv ? q3 : cv;
        a4 += q4 < cv ? q4 : cv;
    }
    std::memcpy(acc, &a0, 32);
    std::memcpy(acc + 16, &a1, 32);
    std::memcpy(acc + 32, &a2, 32);
    std::memcpy(acc + 48, &a3, 32);
    std::memcpy(acc + 64, &a4, 32);
    *sum = s;
}

void score(const std::vector<std::uint64_t>& offsets, const std::vector<std::uint16_t>& entries, int V,
           const std::vector<std::uint16_t>& qt, const std::vector<double>& qsum, const Plan& plan, std::size_t m,
           Scratch& s, float* out) {
    s.acc.resize(static_cast<std::size_t>(V) * kLanes);
    s.msum.resize(static_cast<std::size_t>(V));
    s.pair.resize(plan.pi.size());
    s.rot.resize(static_cast<std::size_t>(plan.rotations));
    const std::size_t base = m * static_cast<std::size_t>(V);
    for (int j = 0; j < V; ++j)
        accumulate(entries.data(), offsets[base + static_cast<std::size_t>(j)], offsets[base + static_cast<std::size_t>(j) + 1],
                   qt.data(), s.acc.data() + static_cast<std::size_t>(j) * kLanes, &s.msum[static_cast<std::size_t>(j)]);
    for (std::size_t k = 0; k < plan.pi.size(); ++k) {
        const int i = plan.pi[k], j = plan.pj[k];
        const std::uint16_t inter = s.acc[static_cast<std::size_t>(j) * kLanes + static_cast<std::size_t>(i)];
        const double qs = qsum[static_cast<std::size_t>(i)], ms = s.msum[static_cast<std::size_t>(j)];
        // No common word: distance_from() is exactly 1 (0 if both views are empty), no division.
        s.pair[k] = inter == 0 ? (qs <= 0 && ms <= 0 ? 0.0 : 1.0) : distance_from(inter, qs, ms);
    }
    // Per rotation the sum over views in view order (as distance_matrix()), rotations side by side.
    std::fill(s.rot.begin(), s.rot.end(), 0.0);
    const auto R = static_cast<std::size_t>(plan.rotations);
    for (int i = 0; i < V; ++i) {
        const int* po = plan.pair_of.data() + static_cast<std::size_t>(i) * R;
        for (std::size_t r = 0; r < R; ++r) s.rot[r] += s.pair[static_cast<std::size_t>(po[r])];
    }
    double best = std::numeric_limits<double>::infinity();
    for (double v : s.rot) best = std::min(best, v);
    *out = static_cast<float>(best);
}

// Little-endian reading and writing.
template <class T>
void put(std::string& b, T v) {
    b.append(reinterpret_cast<const char*>(&v), sizeof v);
}
void put_string(std::string& b, const std::string& s) {
    put(b, static_cast<std::uint32_t>(s.size()));
    b += s;
}

struct Reader {
    const std::string& bytes;
    std::string where;
    std::size_t at = 0;
    void need(std::size_t n) {
        if (bytes.size() - at < n) throw InputError(where + ": truncated at byte " + std::to_string(at));
    }
    template <class T>
    T get() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, bytes.data() + at, sizeof v);
        at += sizeof v;
        return v;
    }
    std::string get_string() {
        const auto n = get<std::uint32_t>();
        need(n);
        std::string s = bytes.substr(at, n);
        at += n;
        return s;
    }
};

}  // namespace

CollectionIndex CollectionIndex::build(const std::vector<std::string>& names, const std::vector<std::string>& classes,
                                       const std::vector<std::vector<views::Histogram>>& models, views::Codebook codebook,
                                       const std::string& method, int simplify) {
    if (names.size() != models.size() || classes.size() != models.size())
        throw InputError("Collection index: " + std::to_string(models.size()) + " models, " + std::to_string(names.size()) +
                         " names and " + std::to_string(classes.size()) + " classes");
    if (models.empty()) throw InputError("Collection index: no models");
    if (codebook.size() > 65535)
        throw InputError("Collection index: a codebook of " + std::to_string(codebook.size()) +
                         " words; the index stores words in 16 bits (at most 65535)");
    CollectionIndex x;
    x.views_ = static_cast<int>(models[0].size());
    if (x.views_ < 1 || x.views_ > kLanes)
        throw InputError("Collection index: " + std::to_string(x.views_) + " views per model (1 to " +
                         std::to_string(kLanes) + ")");
    x.names_ = names;
    x.classes_ = classes;
    x.codebook_ = std::move(codebook);
    x.method_ = method;
    x.simplify_ = simplify;
    std::size_t nnz = 0;
    for (const auto& m : models)
        for (const auto& h : m) nnz += h.size();
    x.offsets_.reserve(models.size() * static_cast<std::size_t>(x.views_) + 1);
    x.entries_.reserve(2 * nnz);
    x.offsets_.push_back(0);
    for (std::size_t k = 0; k < models.size(); ++k) {
        if (models[k].size() != static_cast<std::size_t>(x.views_))
            throw InputError("Collection index: model '" + names[k] + "' has " + std::to_string(models[k].size()) +
                             " views, the first has " + std::to_string(x.views_));
        for (const auto& h : models[k]) {
            double total = 0;
            int last = -1;
            for (const auto& [w, c] : h) {
                if (w <= last || w >= x.codebook_.size() || !(c >= 1) || c != static_cast<float>(static_cast<int>(c)))
                    throw InputError("Collection index: model '" + names[k] +
                                     "': a histogram that is not sorted by word, has a word outside the codebook or "
                                     "a count that is not a positive integer");
                last = w;
                total += c;
                if (total > 65535)  // checked before the 16-bit casts below
                    throw InputError("Collection index: model '" + names[k] + "' has a view of more than 65535 "
                                     "keypoints (16-bit sums: at most 65535)");
                x.entries_.push_back(static_cast<std::uint16_t>(w));
                x.entries_.push_back(static_cast<std::uint16_t>(c));
            }
            x.offsets_.push_back(x.entries_.size() / 2);
        }
    }
    return x;
}

void CollectionIndex::save(const std::string& path) const {
    std::string b = "CFCI";
    put(b, std::uint32_t{1});
    put(b, static_cast<std::uint32_t>(size()));
    put(b, static_cast<std::uint32_t>(views_));
    put(b, static_cast<std::uint32_t>(codebook_.size()));
    put_string(b, method_);
    put(b, static_cast<std::int32_t>(simplify_));
    for (std::size_t k = 0; k < size(); ++k) {
        put_string(b, names_[k]);
        put_string(b, classes_[k]);
    }
    b.append(reinterpret_cast<const char*>(codebook_.words().data()),
             static_cast<std::size_t>(codebook_.words().size()) * sizeof(float));
    b.append(reinterpret_cast<const char*>(offsets_.data()), offsets_.size() * sizeof(std::uint64_t));
    b.append(reinterpret_cast<const char*>(entries_.data()), entries_.size() * sizeof(std::uint16_t));
    io::write_file_atomic(path, b);
}

CollectionIndex CollectionIndex::load(const std::string& path) {
    const std::string bytes = io::read_file(path);
    Reader r{bytes, "'" + path + "'"};
    r.need(4);
    if (bytes.compare(0, 4, "CFCI") != 0) throw InputError(r.where + ": not a canonform collection index");
    r.at = 4;
    if (r.get<std::uint32_t>() != 1) throw InputError(r.where + ": unsupported version");
    const auto n = r.get<std::uint32_t>(), v = r.get<std::uint32_t>(), w = r.get<std::uint32_t>();
    if (n == 0 || v == 0 || v > static_cast<std::uint32_t>(kLanes) || w == 0 || w > 65535)
        throw InputError(r.where + ": bad header (models, views or words out of range)");
    CollectionIndex x;
    x.views_ = static_cast<int>(v);
    x.method_ = r.get_string();
    x.simplify_ = r.get<std::int32_t>();
    for (std::uint32_t k = 0; k < n; ++k) {
        x.names_.push_back(r.get_string());
        x.classes_.push_back(r.get_string());
    }
    views::DescriptorMatrix words(static_cast<Eigen::Index>(w), 128);
    r.need(static_cast<std::size_t>(w) * 128 * sizeof(float));
    std::memcpy(words.data(), bytes.data() + r.at, static_cast<std::size_t>(w) * 128 * sizeof(float));
    r.at += static_cast<std::size_t>(w) * 128 * sizeof(float);
    x.codebook_ = views::Codebook::from_words(std::move(words));
    const std::size_t slots = static_cast<std::size_t>(n) * v + 1;
    r.need(slots * sizeof(std::uint64_t));
    x.offsets_.resize(slots);
    std::memcpy(x.offsets_.data(), bytes.data() + r.at, slots * sizeof(std::uint64_t));
    r.at += slots * sizeof(std::uint64_t);
    for (std::size_t k = 0; k + 1 < slots; ++k)
        if (x.offsets_[k + 1] < x.offsets_[k]) throw InputError(r.where + ": offsets not increasing");
    if (x.offsets_[0] != 0 || (bytes.size() - r.at) != x.offsets_.back() * 2 * sizeof(std::uint16_t))
        throw InputError(r.where + ": the entries do not match the offsets (truncated or trailing bytes)");
    x.entries_.resize(static_cast<std::size_t>(x.offsets_.back()) * 2);
    std::memcpy(x.entries_.data(), bytes.data() + r.at, x.entries_.size() * sizeof(std::uint16_t));
    for (std::size_t e = 0; e < x.entries_.size(); e += 2)
        if (x.entries_[e] >= w || x.entries_[e + 1] == 0) throw InputError(r.where + ": an entry out of range");
    return x;
}

std::vector<float> CollectionIndex::distances(const std::vector<views::Histogram>& query, int threads) const {
    if (query.size() != static_cast<std::size_t>(views_))
        throw InputError("Collection index: the query has " + std::to_string(query.size()) + " views, the index " +
                         std::to_string(views_));
    const auto maps = views::rotation_view_maps();
    if (maps.empty() || maps[0].size() != static_cast<std::size_t>(views_))
        throw InputError("Collection index: the rotation maps are for " + std::to_string(maps.empty() ? 0 : maps[0].size()) +
                         " views, the index has " + std::to_string(views_));
    const Plan plan = make_plan(maps, views_);
    // The query transposed: per word, the count in each query view (lanes), and per view its sum.
    std::vector<std::uint16_t> qt(static_cast<std::size_t>(codebook_.size()) * kLanes, 0);
    std::vector<double> qsum(static_cast<std::size_t>(views_), 0.0);
    for (int i = 0; i < views_; ++i)
        for (const auto& [w, c] : query[static_cast<std::size_t>(i)]) {
            if (w < 0 || w >= codebook_.size() || !(c >= 0) || c > 65535)
                throw InputError("Collection index: a query word outside the codebook or a count beyond 16 bits");
            qt[static_cast<std::size_t>(w) * kLanes + static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(c);
            qsum[static_cast<std::size_t>(i)] += c;
        }
    std::vector<float> out(size());
    ParallelOptions par;
    par.threads = threads;
    par.grain = 256;
    const int workers = parallel_workers(static_cast<std::ptrdiff_t>(size()), par);
    std::vector<Scratch> scratch(static_cast<std::size_t>(workers));
    parallel_for(static_cast<std::ptrdiff_t>(size()), [&](std::ptrdiff_t m, int worker) {
        score(offsets_, entries_, views_, qt, qsum, plan, static_cast<std::size_t>(m), scratch[static_cast<std::size_t>(worker)],
              &out[static_cast<std::size_t>(m)]);
    }, par);
    return out;
}

std::vector<IndexMatch> CollectionIndex::top(const std::vector<views::Histogram>& query, std::size_t k, int threads) const {
    const std::vector<float> d = distances(query, threads);
    std::vector<std::size_t> order(d.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    k = std::min(k, order.size());
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                      [&](std::size_t a, std::size_t b) { return d[a] < d[b] || (d[a] == d[b] && a < b); });
    std::vector<IndexMatch> out;
    for (std::size_t r = 0; r < k; ++r) out.push_back({order[r], names_[order[r]], classes_[order[r]], d[order[r]]});
    return out;
}

CollectionIndex index_method_folder(const std::string& folder, const std::string& method, int simplify) {
    const auto rows = io::read_csv(folder + "/models.csv");
    std::vector<std::string> names, classes;
    for (std::size_t r = 1; r < rows.size(); ++r) {
        if (rows[r].size() < 2) throw InputError("'" + folder + "/models.csv': row " + std::to_string(r + 1) + " is not name,class");
        names.push_back(rows[r][0]);
        classes.push_back(rows[r][1]);
    }
    std::vector<std::vector<views::Histogram>> models(names.size());
    parallel_for(static_cast<std::ptrdiff_t>(names.size()), [&](std::ptrdiff_t k, int) {
        views::ModelDescriptor d = views::read_descriptor(folder + "/descriptors/" + names[static_cast<std::size_t>(k)] + ".cfvd");
        if (d.codebook_words == 0)
            throw InputError("'" + folder + "/descriptors/" + names[static_cast<std::size_t>(k)] + ".cfvd' has no histograms");
        models[static_cast<std::size_t>(k)] = std::move(d.histograms);
    });
    return CollectionIndex::build(names, classes, models, views::Codebook::load(folder + "/codebook.bin"), method, simplify);
}

}  // namespace canonform::retrieval
