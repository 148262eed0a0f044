// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/collection_index.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/common/parallel.h"
#include "canonform/retrieval/collection_index_detail.h"
#include "canonform/views/view_directions.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>

namespace canonform::retrieval {

namespace detail {

void put_leb128(std::vector<std::uint8_t>& out, std::uint32_t v) {
    while (v >= 0x80) {
        out.push_back(static_cast<std::uint8_t>(v | 0x80));
        v >>= 7;
    }
    out.push_back(static_cast<std::uint8_t>(v));
}

void encode_view(const views::Histogram& h, int words, std::vector<std::uint8_t>& out,
                 const std::string& model) {
    put_leb128(out, static_cast<std::uint32_t>(h.size()));
    int prev = -1;
    double total = 0;
    for (const auto& [w, c] : h) {
        if (w <= prev || w >= words || !(c >= 1) || c != static_cast<float>(static_cast<int>(c)))
            throw InputError("Collection index: model '" + model +
                             "': a histogram that is not sorted by word, has a word outside the codebook or "
                             "a count that is not a positive integer");
        total += c;
        if (total > 65535)  // checked before the 16-bit casts below
            throw InputError("Collection index: model '" + model +
                             "' has a view of more than 65535 "
                             "keypoints (16-bit sums: at most 65535)");
        const int gap = w - prev, count = static_cast<int>(c);
        if (count == 1 && gap <= 240) {
            out.push_back(static_cast<std::uint8_t>(gap - 1));
        } else if (count >= 2 && count <= 16 && gap <= 256) {
            out.push_back(static_cast<std::uint8_t>(238 + count));
            out.push_back(static_cast<std::uint8_t>(gap - 1));
        } else {
            out.push_back(255);
            out.push_back(static_cast<std::uint8_t>(gap & 0xFF));
            out.push_back(static_cast<std::uint8_t>(gap >> 8));
            out.push_back(static_cast<std::uint8_t>(count & 0xFF));
            out.push_back(static_cast<std::uint8_t>(count >> 8));
        }
        prev = w;
    }
}

/// A view's entry count, a little-endian base-128 varint, read from a model that check_model()
/// has accepted (so without bounds checks); p moves past it.
inline std::uint32_t read_entry_count(const std::uint8_t*& p) {
    std::uint32_t n = 0;
    for (int shift = 0;; shift += 7) {
        const std::uint8_t b = *p++;
        n |= static_cast<std::uint32_t>(b & 0x7F) << shift;
        if (!(b & 0x80)) return n;
    }
}

bool check_model(const std::uint8_t* p, const std::uint8_t* end, int views, int words) {
    for (int v = 0; v < views; ++v) {
        std::uint32_t n = 0;
        int shift = 0;
        for (;;) {
            if (p >= end || shift > 28) return false;
            const std::uint8_t b = *p++;
            n |= static_cast<std::uint32_t>(b & 0x7F) << shift;
            shift += 7;
            if (!(b & 0x80)) break;
        }
        long w = -1, total = 0;
        for (std::uint32_t e = 0; e < n; ++e) {
            if (p >= end) return false;
            const std::uint8_t b = *p++;
            long gap = 0, count = 0;
            if (b < 240) {
                gap = b + 1;
                count = 1;
            } else if (b < 255) {
                if (p >= end) return false;
                count = b - 238;
                gap = *p++ + 1;
            } else {
                if (end - p < 4) return false;
                gap = p[0] | (p[1] << 8);
                count = p[2] | (p[3] << 8);
                p += 4;
                if (gap < 1 || count < 1) return false;
            }
            w += gap;
            total += count;
            if (w >= words || total > 65535) return false;
        }
    }
    return p == end;
}

void unpack(const std::uint8_t* p, int views, std::vector<views::Histogram>& out) {
    out.resize(static_cast<std::size_t>(views));
    for (int v = 0; v < views; ++v) {
        const std::uint32_t n = read_entry_count(p);
        views::Histogram& h = out[static_cast<std::size_t>(v)];
        h.clear();
        int w = -1;
        for (std::uint32_t e = 0; e < n; ++e) {
            const std::uint8_t b = *p++;
            int count;
            if (b < 240) {
                w += b + 1;
                count = 1;
            } else if (b < 255) {
                count = b - 238;
                w += *p++ + 1;
            } else {
                w += p[0] | (p[1] << 8);
                count = p[2] | (p[3] << 8);
                p += 4;
            }
            h.emplace_back(w, static_cast<float>(count));
        }
    }
}

}  // namespace detail

namespace {

constexpr int kCubeRotations = 24;  // views::rotation_view_maps()

/// Where clock matching's view pairs are. The rotations move a view only within its orbit
/// (summary_search.h: four orbits of 6, 12, 24 and 24 views), so the pairs any rotation uses are
/// the orbit-by-orbit blocks of the 66 x 66 pairs: 1332. Each orbit owns a block of lanes that
/// starts at a multiple of 16 (16, 16, 32 and 32 lanes: `width` 96); a view's lane is its
/// block's start plus its rank in the orbit. The query's counts sit in its views' lanes; a model
/// view's intersections are accumulated over its own block's lanes only (one or two registers of
/// 16, not all 66 views) into the row of its lane; each block's pair distances are computed side
/// by side. pair_of[v * R + r]: the pair of (query view v, model view maps[r][v]) - the query's
/// views in order; pair_of_model[v * R + r]: the pair of (query view maps[r][v], model view v) -
/// the model's views in order.
struct Plan {
    struct Block {
        int start = 0, size = 0, base = 0;  // lanes [start, start + size), distances at base
    };
    int width = 0;                                      // lanes
    std::vector<int> lane;                              // per view
    std::vector<int> registers;                         // per view: its block's registers of 16 lanes
    std::vector<int> view_start, view_size, view_base;  // per view: its block's start, size, base
    std::vector<Block> blocks;
    int pairs = 0;
    std::vector<int> pair_of, pair_of_model;  // views x kCubeRotations
};

Plan make_plan(const std::vector<std::vector<int>>& maps, int views) {
    Plan p;
    const auto R = maps.size();
    if (R != kCubeRotations)
        throw InputError("Collection index: " + std::to_string(R) + " rotation maps, not the cube's " +
                         std::to_string(kCubeRotations));
    int count = 0;
    const std::vector<int> orbit = view_orbits(maps, views, &count);
    p.lane.resize(static_cast<std::size_t>(views));
    p.registers.resize(static_cast<std::size_t>(views));
    for (int o = 0; o < count; ++o) {
        Plan::Block b;
        b.start = p.width;
        b.base = p.pairs;
        for (int v = 0; v < views; ++v)
            if (orbit[static_cast<std::size_t>(v)] == o)
                p.lane[static_cast<std::size_t>(v)] = b.start + b.size++;
        const int regs = (b.size + 15) / 16;
        for (int v = 0; v < views; ++v)
            if (orbit[static_cast<std::size_t>(v)] == o) p.registers[static_cast<std::size_t>(v)] = regs;
        p.width += 16 * regs;
        p.pairs += b.size * b.size;
        p.blocks.push_back(b);
    }
    for (int v = 0; v < views; ++v) {
        const Plan::Block& b = p.blocks[static_cast<std::size_t>(orbit[static_cast<std::size_t>(v)])];
        p.view_start.push_back(b.start);
        p.view_size.push_back(b.size);
        p.view_base.push_back(b.base);
    }
    auto pair = [&](int query_view, int model_view) {
        const Plan::Block& b =
            p.blocks[static_cast<std::size_t>(orbit[static_cast<std::size_t>(query_view)])];
        return b.base + (p.lane[static_cast<std::size_t>(model_view)] - b.start) * b.size +
               (p.lane[static_cast<std::size_t>(query_view)] - b.start);
    };
    p.pair_of.resize(static_cast<std::size_t>(views) * R);
    p.pair_of_model.resize(static_cast<std::size_t>(views) * R);
    for (int v = 0; v < views; ++v)
        for (std::size_t r = 0; r < R; ++r) {
            const int image = maps[r][static_cast<std::size_t>(v)];
            p.pair_of[static_cast<std::size_t>(v) * R + r] = pair(v, image);
            p.pair_of_model[static_cast<std::size_t>(v) * R + r] = pair(image, v);
        }
    return p;
}

struct Scratch {
    std::vector<std::uint16_t> acc;   // width x width: a row per lane
    std::vector<std::uint32_t> msum;  // per lane
    std::vector<double> pair;
};

/// 16 and 32 lanes of 16-bit counts (one AVX2 register, and one AVX-512 or two AVX2 registers;
/// two and four SSE2 ones in the default build).
typedef std::uint16_t Lanes __attribute__((vector_size(32)));
typedef std::uint16_t Lanes2 __attribute__((vector_size(64)));
#if defined(_WIN32)  // no 64-byte stack alignment to count on (below): 16 lanes at a time
constexpr bool kPairedLanes = false;
#else
constexpr bool kPairedLanes = true;
#endif

/// One view's entries, decoded, accumulated over R registers of 16 lanes (in pairs, and one alone
/// if R is odd) from `q0` on: per entry (word w, count c) acc += min(query counts of w, c) - the
/// hot loop. Returns the bytes after it.
template <int R>
inline const std::uint8_t* accumulate_view(const std::uint8_t* p, std::uint32_t n, const std::uint16_t* qt,
                                           int width, std::uint16_t* out, std::uint32_t* sum) {
    constexpr int P = kPairedLanes ? R / 2 : 0, S = R - 2 * P;  // pairs, single registers
    Lanes2 a[P > 0 ? P : 1] = {};
    Lanes h[S > 0 ? S : 1] = {};
    const Lanes2 ones2 = Lanes2{} + 1;
    const Lanes ones = Lanes{} + 1;
    std::uint32_t more = 0;  // keypoints beyond one per entry
    int w = -1;
    for (std::uint32_t e = 0; e < n; ++e) {
        const std::uint32_t b = *p++;
        Lanes2 cv2 = ones2;  // nine entries in ten have count 1
        Lanes cv = ones;
        if (b < 240) {
            w += static_cast<int>(b) + 1;
        } else {
            std::uint16_t c;
            if (b < 255) {
                c = static_cast<std::uint16_t>(b - 238);
                w += *p++ + 1;
            } else {
                w += p[0] | (p[1] << 8);
                c = static_cast<std::uint16_t>(p[2] | (p[3] << 8));
                p += 4;
            }
            more += c - 1u;
            cv2 = Lanes2{} + c;
            cv = Lanes{} + c;
        }
        const std::uint16_t* q = qt + static_cast<std::size_t>(w) * static_cast<std::size_t>(width);
        for (int k = 0; k < P; ++k) {
            Lanes2 qk;
            std::memcpy(&qk, q + 32 * k, 64);
            a[k] += qk < cv2 ? qk : cv2;
        }
        for (int k = 0; k < S; ++k) {
            Lanes qk;
            std::memcpy(&qk, q + 32 * P + 16 * k, 32);
            h[k] += qk < cv ? qk : cv;
        }
    }
    for (int k = 0; k < P; ++k) std::memcpy(out + 32 * k, &a[k], 64);
    for (int k = 0; k < S; ++k) std::memcpy(out + 32 * P + 16 * k, &h[k], 32);
    *sum = n + more;
    return p;
}

/// What score_views() reads and writes: the plan's arrays, the query's, the scratch rows.
struct ViewWork {
    const int* lane;           // per view
    const int* registers;      // per view
    const int* block_start;    // per view: its block's first lane
    const int* block_size;     // per view: its block's lanes
    const int* block_base;     // per view: its block's first pair
    const int* pair_of_model;  // views x kCubeRotations (Plan::pair_of_model)
    int width;
    const std::uint16_t* qt;
    const double* qsum;
    std::uint16_t* acc;
    std::uint32_t* msum;
    double* pair;
    double* rot;  // kCubeRotations partial sums over the model's views in order
};

/// Decodes the model's views in order and, per view, accumulates its intersections over its
/// block's lanes (qt: the query's counts from the block's first lane on) into the row of its lane
/// (msum[lane]: its keypoints), computes that row's pair distances (bag_of_features.cpp's
/// 1 - inter / max(sums), 0 if both views are empty: divisions and min/max, rounded the same in
/// every lane width) and adds them to the rotations' sums over the model's views in order. After
/// each view from `check_from` on, if every rotation's partial sum exceeds `bound` the model is
/// given up (false): the sums only grow. True when every view was scored.
CANONFORM_CLONES_AVX512 bool score_views(const std::uint8_t* p, int views, const ViewWork& k, double bound,
                                         int check_from) {
    double rot[kCubeRotations] = {};
    for (int j = 0; j < views; ++j) {
        const std::uint32_t n = detail::read_entry_count(p);
        const int l = k.lane[j], start = k.block_start[j], size = k.block_size[j];
        std::uint16_t* out = k.acc + static_cast<std::size_t>(l) * static_cast<std::size_t>(k.width) + start;
        const std::uint16_t* q = k.qt + start;
        switch (k.registers[j]) {
            case 1:
                p = accumulate_view<1>(p, n, q, k.width, out, &k.msum[l]);
                break;
            case 2:
                p = accumulate_view<2>(p, n, q, k.width, out, &k.msum[l]);
                break;
            case 3:
                p = accumulate_view<3>(p, n, q, k.width, out, &k.msum[l]);
                break;
            case 4:
                p = accumulate_view<4>(p, n, q, k.width, out, &k.msum[l]);
                break;
            default:
                p = accumulate_view<5>(p, n, q, k.width, out, &k.msum[l]);
                break;
        }
        // bag_of_features.cpp clamps 1 - inter / max to [0, 1]: here the intersection is an
        // integer at most the larger sum, so the quotient is in [0, 1] already (rounding is
        // monotone) and the clamp never acts.
        const double ms = k.msum[l];
        const double* qs = k.qsum + start;
        double* d = k.pair + k.block_base[j] + (l - start) * size;
        for (int x = 0; x < size; ++x) {
            const double m = qs[x] > ms ? qs[x] : ms;
            const double v = 1.0 - static_cast<double>(out[x]) / (m > 0 ? m : 1.0);
            d[x] = m > 0 ? v : 0.0;
        }
        const int* po = k.pair_of_model + static_cast<std::size_t>(j) * kCubeRotations;
        for (int r = 0; r < kCubeRotations; ++r) rot[r] += k.pair[po[r]];
        if (j >= check_from) {
            double least = rot[0];
            for (int r = 1; r < kCubeRotations; ++r) least = rot[r] < least ? rot[r] : least;
            if (least > bound) return false;
        }
    }
    for (int r = 0; r < kCubeRotations; ++r) k.rot[r] = rot[r];
    return true;
}

constexpr int kPrefetchLines = 64;  // at most, of a candidate's bytes (about 2.4 kB on real collections)

/// The smallest of the 24 rotation sums: per rotation the sum of its pairs' distances over the
/// views in order (as distance_matrix()), the rotations side by side in registers (the same
/// additions in the same order as one rotation at a time).
CANONFORM_CLONES_AVX512 double smallest_rotation_sum(const double* pair, const int* pair_of, int views) {
    double rot[kCubeRotations] = {};
    for (int v = 0; v < views; ++v) {
        const int* po = pair_of + static_cast<std::size_t>(v) * kCubeRotations;
        for (int r = 0; r < kCubeRotations; ++r) rot[r] += pair[po[r]];
    }
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < kCubeRotations; ++r) best = std::min(best, rot[r]);
    return best;
}

/// The query transposed: per word, the count in each query view (its lane), and per lane its sum.
struct Query {
    std::vector<std::uint16_t> storage;
    std::uint16_t* qt =
        nullptr;  // words x width in `storage`, from a 64-byte boundary (a block's lanes in one cache line)
    std::vector<double> qsum;  // width
};

/// Clock-matching distance of the query to the model whose bytes are at `p`; `model_order`: the
/// rotation sums over the model's views (the matrix's order when the model comes first), else
/// over the query's. +infinity if the model was given up: every rotation's sum over its first
/// views exceeded `bound` (so does its distance, up to the last bits of the sums' order).
float score(const std::uint8_t* p, int V, const Query& q, const Plan& plan, bool model_order, double bound,
            Scratch& s) {
    const auto width = static_cast<std::size_t>(plan.width);
    s.acc.resize(width * width);
    s.msum.resize(width);
    s.pair.resize(static_cast<std::size_t>(plan.pairs));
    double rot[kCubeRotations];
    const ViewWork k{plan.lane.data(),
                     plan.registers.data(),
                     plan.view_start.data(),
                     plan.view_size.data(),
                     plan.view_base.data(),
                     plan.pair_of_model.data(),
                     plan.width,
                     q.qt,
                     q.qsum.data(),
                     s.acc.data(),
                     s.msum.data(),
                     s.pair.data(),
                     rot};
    // The first views' sums are too small to exceed any useful bound: no checks before them.
    constexpr int kCheckFrom = 16;
    if (!score_views(p, V, k, bound, bound < std::numeric_limits<double>::infinity() ? kCheckFrom : V))
        return std::numeric_limits<float>::infinity();
    if (model_order) return static_cast<float>(*std::min_element(rot, rot + kCubeRotations));
    return static_cast<float>(smallest_rotation_sum(s.pair.data(), plan.pair_of.data(), V));
}

}  // namespace

struct CollectionIndex::Builder::Parts {
    CollectionIndex x;
};

CollectionIndex::Builder::Builder(views::Codebook codebook, std::string method, int simplify, int views)
    : parts_(std::make_shared<Parts>()) {
    if (codebook.size() > 65535)
        throw InputError("Collection index: a codebook of " + std::to_string(codebook.size()) +
                         " words; the index stores words in 16 bits (at most 65535)");
    if (views < 1 || views > detail::kMaxViews)
        throw InputError("Collection index: " + std::to_string(views) + " views per model (1 to " +
                         std::to_string(detail::kMaxViews) + ")");
    CollectionIndex& x = parts_->x;
    x.views_ = views;
    x.codebook_ = std::move(codebook);
    x.method_ = std::move(method);
    x.simplify_ = simplify;
    x.offsets_.push_back(0);
}

void CollectionIndex::Builder::add(const std::string& name, const std::string& cls,
                                   const std::vector<views::Histogram>& views) {
    CollectionIndex& x = parts_->x;
    if (views.size() != static_cast<std::size_t>(x.views_))
        throw InputError("Collection index: model '" + name + "' has " + std::to_string(views.size()) +
                         " views, the index " + std::to_string(x.views_));
    if (x.names_.size() >= std::numeric_limits<std::uint32_t>::max())
        throw InputError("Collection index: more than 2^32 - 1 models");
    const std::size_t before = x.data_.size();
    try {
        for (const auto& h : views) detail::encode_view(h, x.codebook_.size(), x.data_, name);
    } catch (...) {
        x.data_.resize(before);
        throw;
    }
    x.offsets_.push_back(x.data_.size());
    x.names_.push_back(name);
    x.classes_.push_back(cls);
}

std::size_t CollectionIndex::Builder::size() const {
    return parts_->x.names_.size();
}

CollectionIndex CollectionIndex::Builder::finish(const SummaryOptions* summary, int threads) {
    CollectionIndex x = std::move(parts_->x);
    parts_ = std::make_shared<Parts>();
    if (x.names_.empty()) throw InputError("Collection index: no models");
    x.data_.shrink_to_fit();
    if (summary) x.train_first_pass(*summary, threads);
    return x;
}

void CollectionIndex::train_first_pass(const SummaryOptions& options, int threads) {
    const auto maps = views::rotation_view_maps();
    if (maps.empty() || maps[0].size() != static_cast<std::size_t>(views_)) return;  // exact queries only
    orbit_of_view_ = view_orbits(maps, views_, &orbit_count_);
    const std::uint32_t dims = static_cast<std::uint32_t>(options.orbits ? orbit_count_ : 1) *
                               static_cast<std::uint32_t>(codebook_.size());
    const std::size_t n = size();
    const std::size_t s = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, options.sample)));
    std::vector<Summary> sample(s);
    ParallelOptions par;
    par.threads = threads;
    par.grain = 16;
    const int workers = parallel_workers(static_cast<std::ptrdiff_t>(std::max(s, n)), par);
    std::vector<std::vector<views::Histogram>> scratch(static_cast<std::size_t>(workers));
    parallel_for(
        static_cast<std::ptrdiff_t>(s),
        [&](std::ptrdiff_t k, int w) {
            const std::size_t m = static_cast<std::size_t>(k) * n / s;
            auto& h = scratch[static_cast<std::size_t>(w)];
            detail::unpack(model_bytes(m), views_, h);
            sample[static_cast<std::size_t>(k)] =
                SummarySearch::summarise(h, orbit_of_view_, orbit_count_, codebook_.size(), options);
        },
        par);
    first_ = SummarySearch::train(sample, dims, options, threads);
    sample.clear();
    std::vector<std::int8_t> codes(n * static_cast<std::size_t>(first_.dims()));
    std::vector<std::vector<std::int8_t>> code(
        static_cast<std::size_t>(workers), std::vector<std::int8_t>(static_cast<std::size_t>(first_.dims())));
    parallel_for(
        static_cast<std::ptrdiff_t>(n),
        [&](std::ptrdiff_t k, int w) {
            auto& h = scratch[static_cast<std::size_t>(w)];
            detail::unpack(model_bytes(static_cast<std::size_t>(k)), views_, h);
            std::int8_t* c = code[static_cast<std::size_t>(w)].data();
            first_.encode(
                SummarySearch::summarise(h, orbit_of_view_, orbit_count_, codebook_.size(), options), c);
            SummarySearch::put_split(codes.data(), n, first_.dims(), static_cast<std::size_t>(k), c);
        },
        par);
    first_.set_split_codes(std::move(codes));
}

CollectionIndex CollectionIndex::build(const std::vector<std::string>& names,
                                       const std::vector<std::string>& classes,
                                       const std::vector<std::vector<views::Histogram>>& models,
                                       views::Codebook codebook, const std::string& method, int simplify) {
    if (names.size() != models.size() || classes.size() != models.size())
        throw InputError("Collection index: " + std::to_string(models.size()) + " models, " +
                         std::to_string(names.size()) + " names and " + std::to_string(classes.size()) +
                         " classes");
    if (models.empty()) throw InputError("Collection index: no models");
    Builder b(std::move(codebook), method, simplify, static_cast<int>(models[0].size()));
    for (std::size_t k = 0; k < models.size(); ++k) b.add(names[k], classes[k], models[k]);
    const SummaryOptions defaults;
    return b.finish(&defaults);
}

const std::uint8_t* CollectionIndex::model_bytes(std::size_t m) const {
    if (!mapped_) return data_.data() + offsets_[m];
    const std::uint8_t* p = mapped_.get() + offsets_[m];
    std::atomic<std::uint8_t>& checked = checked_[m];
    if (!checked.load(std::memory_order_relaxed)) {
        if (!detail::check_model(p, mapped_.get() + offsets_[m + 1], views_, codebook_.size()))
            throw InputError(
                "Collection index: model " + std::to_string(m) + " ('" + names_[m] +
                "') is not well-formed: the index file is damaged (run `canonform index` again)");
        checked.store(1, std::memory_order_relaxed);
    }
    return p;
}

std::vector<views::Histogram> CollectionIndex::histograms(std::size_t m) const {
    if (m >= size())
        throw InputError("Collection index: model " + std::to_string(m) + " of " + std::to_string(size()));
    std::vector<views::Histogram> h;
    detail::unpack(model_bytes(m), views_, h);
    return h;
}

namespace {

Query transpose_query(const std::vector<views::Histogram>& query, int views, int words, const Plan& plan) {
    if (query.size() != static_cast<std::size_t>(views))
        throw InputError("Collection index: the query has " + std::to_string(query.size()) +
                         " views, the index " + std::to_string(views));
    Query q;
    const auto width = static_cast<std::size_t>(plan.width);
    q.storage.assign(static_cast<std::size_t>(words) * width + 32, 0);
    const auto misalign = reinterpret_cast<std::uintptr_t>(q.storage.data()) % 64;
    q.qt = q.storage.data() + (misalign ? (64 - misalign) / 2 : 0);
    q.qsum.assign(width, 0.0);
    for (int i = 0; i < views; ++i)
        for (const auto& [w, c] : query[static_cast<std::size_t>(i)]) {
            if (w < 0 || w >= words || !(c >= 0) || c > 65535 || c != static_cast<float>(static_cast<int>(c)))
                throw InputError(
                    "Collection index: a query word outside the codebook or a count that is not an "
                    "integer of 16 bits");
            const auto l = static_cast<std::size_t>(plan.lane[static_cast<std::size_t>(i)]);
            q.qt[static_cast<std::size_t>(w) * width + l] = static_cast<std::uint16_t>(c);
            q.qsum[l] += c;
        }
    return q;
}

Plan plan_for(int views) {
    const auto maps = views::rotation_view_maps();
    if (maps.empty() || maps[0].size() != static_cast<std::size_t>(views))
        throw InputError("Collection index: the rotation maps are for " +
                         std::to_string(maps.empty() ? 0 : maps[0].size()) + " views, the index has " +
                         std::to_string(views));
    return make_plan(maps, views);
}

}  // namespace

std::vector<float> CollectionIndex::distances(const std::vector<views::Histogram>& query, int threads,
                                              std::ptrdiff_t self) const {
    std::vector<std::uint32_t> all(size());
    std::iota(all.begin(), all.end(), 0u);
    return distances(query, all, threads, self);
}

std::vector<float> CollectionIndex::distances(const std::vector<views::Histogram>& query,
                                              const std::vector<std::uint32_t>& models, int threads,
                                              std::ptrdiff_t self) const {
    return scores(query, models, threads, self, 0);
}

std::vector<float> CollectionIndex::scores(const std::vector<views::Histogram>& query,
                                           const std::vector<std::uint32_t>& models, int threads,
                                           std::ptrdiff_t self, std::size_t keep) const {
    const Plan plan = plan_for(views_);
    const Query q = transpose_query(query, views_, codebook_.size(), plan);
    for (std::uint32_t m : models)
        if (m >= size())
            throw InputError("Collection index: model " + std::to_string(m) + " of " +
                             std::to_string(size()));
    std::vector<float> out(models.size());
    ParallelOptions par;
    par.threads = threads;
    par.grain = 256;
    const int workers = parallel_workers(static_cast<std::ptrdiff_t>(models.size()), par);
    std::vector<Scratch> scratch(static_cast<std::size_t>(workers));
    // Per worker its `keep` smallest (distance, model) so far, a max-heap: a model whose distance
    // exceeds the largest of them cannot be among the `keep` smallest of all (that worker's
    // `keep` are smaller), so it is given up as soon as its partial sums show it.
    typedef std::pair<float, std::uint32_t> Kept;
    std::vector<std::vector<Kept>> kept(static_cast<std::size_t>(keep > 0 ? workers : 0));
    const std::uint8_t* base = mapped_ ? mapped_.get() : data_.data();
    parallel_for(
        static_cast<std::ptrdiff_t>(models.size()),
        [&](std::ptrdiff_t k, int worker) {
            const std::uint32_t m = models[static_cast<std::size_t>(k)];
            // The next model's bytes on their way while this one is scored (candidates are
            // scattered; a hint only: no fault, no effect on the result).
            if (static_cast<std::size_t>(k) + 1 < models.size()) {
                const std::uint32_t n = models[static_cast<std::size_t>(k) + 1];
                const std::uint64_t from = offsets_[n] & ~std::uint64_t{63},
                                    to = std::min(offsets_[n + 1], from + 64 * kPrefetchLines);
                for (std::uint64_t at = from; at < to; at += 64) __builtin_prefetch(base + at);
            }
            double bound = std::numeric_limits<double>::infinity();
            std::vector<Kept>* heap = keep > 0 ? &kept[static_cast<std::size_t>(worker)] : nullptr;
            if (heap && heap->size() == keep)
                // Given up only if the partial sums exceed the next float above the largest kept
                // by a margin larger than the sums' rounding in another order (66 terms: about
                // 1.5e-14 of the sum): the exact distance then rounds above it.
                bound = static_cast<double>(
                            std::nextafter(heap->front().first, std::numeric_limits<float>::infinity())) *
                        (1 + 1e-12);
            const float d =
                score(model_bytes(m), views_, q, plan, self >= 0 && static_cast<std::ptrdiff_t>(m) < self,
                      bound, scratch[static_cast<std::size_t>(worker)]);
            out[static_cast<std::size_t>(k)] = d;
            if (heap) {
                const Kept e{d, m};
                if (heap->size() < keep) {
                    heap->push_back(e);
                    std::push_heap(heap->begin(), heap->end());
                } else if (e < heap->front()) {
                    std::pop_heap(heap->begin(), heap->end());
                    heap->back() = e;
                    std::push_heap(heap->begin(), heap->end());
                }
            }
        },
        par);
    return out;
}

namespace {

/// The k smallest (distance, model) of `d` over `models`, as matches.
std::vector<IndexMatch> smallest(const std::vector<float>& d, const std::vector<std::uint32_t>& models,
                                 std::size_t k, const std::vector<std::string>& names,
                                 const std::vector<std::string>& classes) {
    std::vector<std::size_t> order(d.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    k = std::min(k, order.size());
    std::partial_sort(
        order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
        [&](std::size_t a, std::size_t b) { return d[a] < d[b] || (d[a] == d[b] && models[a] < models[b]); });
    std::vector<IndexMatch> out;
    for (std::size_t r = 0; r < k; ++r) {
        const std::size_t m = models[order[r]];
        out.push_back({m, names[m], classes[m], d[order[r]]});
    }
    return out;
}

}  // namespace

std::vector<IndexMatch> CollectionIndex::top(const std::vector<views::Histogram>& query, std::size_t k,
                                             int threads) const {
    SearchOptions o;
    o.exact = true;
    o.threads = threads;
    return search(query, k, o);
}

bool CollectionIndex::two_stage(const SearchOptions& o) const {
    return !o.exact && first_.trained() && (size() > kTwoStageAbove || o.candidates > 0);
}

std::string CollectionIndex::default_candidates_rule() {
    return "max(" + std::to_string(kCandidatesMin) + ", " + std::to_string(kCandidatesPerK) + " K, N / " +
           std::to_string(kCandidatesShare) + ")";
}

std::size_t CollectionIndex::default_candidates(std::size_t k) const {
    return std::min(size(), std::max({kCandidatesMin, kCandidatesPerK * k, size() / kCandidatesShare}));
}

std::vector<std::int8_t> CollectionIndex::code(const std::vector<views::Histogram>& query) const {
    if (!first_.trained())
        throw InputError(
            "Collection index: no first pass (an index of version 1: run `canonform index` again)");
    if (query.size() != static_cast<std::size_t>(views_))
        throw InputError("Collection index: the query has " + std::to_string(query.size()) +
                         " views, the index " + std::to_string(views_));
    std::vector<std::int8_t> c(static_cast<std::size_t>(first_.dims()));
    first_.encode(
        SummarySearch::summarise(query, orbit_of_view_, orbit_count_, codebook_.size(), first_.options()),
        c.data());
    return c;
}

std::vector<IndexMatch> CollectionIndex::search(const std::vector<views::Histogram>& query, std::size_t k,
                                                const SearchOptions& o) const {
    std::vector<std::uint32_t> models;
    if (two_stage(o)) {
        const std::size_t c = std::max(k, o.candidates > 0 ? o.candidates : default_candidates(k));
        const auto qc = code(query);
        models = first_.nearest(qc.data(), c, o.threads);
    } else {
        models.resize(size());
        std::iota(models.begin(), models.end(), 0u);
    }
    const std::vector<float> d = scores(query, models, o.threads, o.self, std::min(k, models.size()));
    return smallest(d, models, k, names_, classes_);
}

}  // namespace canonform::retrieval
