// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: an indexed collection - the bag-of-features histograms of a retrieval run packed for
// queries: the K nearest models of a query model by clock matching over the 66 views, either
// exhaustively or in two stages (a first pass proposes candidates, clock matching ranks them).
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape
// retrieval using Clock Matching and Bag-of-Features", Machine Vision and Applications 24, 2013
// (Sec. 3.4, clock matching); the distance is bag_of_features.h's, computed differently:
//
//   D(Q, M) = min over rotations r of sum_i d(q_i, m_{maps[r][i]}),
//   d(a, b) = 1 - sum_w min(a_w, b_w) / max(sum a, sum b)   (0 if both empty)
//
// Departures (storage and order of work only; the values are those of views::distance_matrix()):
// - Counts are integers (keypoints per word). A model is stored as bytes, view after view: the
//   view's number of entries (LEB128), then per entry, words ascending from -1: one byte b < 240
//   for a word b + 1 after the previous with count 1; b in 240..254 for count b - 238 followed by
//   one byte g - 1 for a word gap g <= 256; 255 followed by the gap and the count as two u16
//   (anything else). About 1.05 bytes per non-zero on real collections, a quarter of (u16 word,
//   u16 count) pairs. A codebook of more than 65535 words or a view of more than 65535 keypoints
//   is refused (InputError).
// - Per model, the intersections of all 66 query views with each model view are accumulated at
//   once, word by word, from the query's histograms transposed (word -> 66 counts): exact integer
//   sums (the same values as the float sums of distance_matrix()), in SIMD lanes (16 or 32 at a
//   time: AVX-512, AVX2 or SSE2 code chosen at run time, the same integers); then d() and the 24
//   rotation sums in double, side by side (each rotation's sum in view order: the same bits on
//   every path); the next candidate's bytes are prefetched. The matrix computes D(A, B) with the
//   earlier model as A, summing over A's views in order; a query that names its own place in the
//   collection (`self`) gets exactly the matrix's value for every model: for models before it the
//   sums run over the model's views (the matrix's order), otherwise over the query's. Without
//   `self` the sums run over the query's views (equal to the matrix's up to the last bit of the
//   double sum).
// - Models are scored in parallel (parallel_for), the K smallest kept (ties by model order). A
//   top-K query gives a model up part way: the rotations' sums over the model's first views
//   (model order) only grow, so once every one of them exceeds the largest of the K distances its
//   worker holds (with a margin above the last bits of the sums' order and the float rounding) the
//   model cannot be among the K nearest; the answer is that of scoring every model to the end.
//   The two-stage query scores its candidates nearest code first, so the K held are near early.
// - Two stages (summary_search.h): the first pass's `candidates` nearest codes, then their exact
//   distances, the K smallest kept. The distances returned are exact; a model the first pass
//   misses is missing from the answer (recall measured in bench/bench_query.cpp, docs/scale.md).
//
// File format (little endian, written atomically):
//   "CFCI", u32 version (2), u32 models N, u32 views V, u32 words W,
//   u32 length + bytes: the method (MethodSpec::to_string()), i32 simplify,
//   N x (u32 length + name, u32 length + class),
//   W x 128 f32 codebook words,
//   (N + 1) x u64 byte offsets of the models, then the model bytes (above),
//   u32 first pass present (0 or 1); if 1: i32 dims d, u8 orbits, u8 square roots, i32 sample,
//   i32 iterations, u64 seed, u32 summary coordinates S, f32 scale, d x f32 offsets,
//   S x d f32 axes, N x d i8 codes.
// Version 1 (the models as (N*V + 1) x u64 entry offsets and u16 (word, count) pairs, no first
// pass) is still read; such an index answers exhaustively.
#pragma once

#include "canonform/retrieval/summary_search.h"
#include "canonform/views/bag_of_features.h"
#include "canonform/views/codebook.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace canonform::retrieval {

/// One answer of a query.
struct IndexMatch {
    std::size_t model = 0;  ///< index in the collection
    std::string name, cls;
    float distance = 0;
};

/// How a query searches.
struct SearchOptions {
    /// Exhaustive clock matching over every model, never the first pass.
    bool exact = false;
    /// First-pass candidates (0: automatic - default_candidates()).
    std::size_t candidates = 0;
    /// The query's own model index, for distances in the distance matrix's order (-1: none).
    std::ptrdiff_t self = -1;
    /// Threads (<= 0: every core); the answer does not depend on it.
    int threads = 0;
};

/// The histograms of a collection, packed for queries.
class CollectionIndex {
public:
    /// Above this many models a query uses the first pass by default (if the index has one):
    /// below it an exhaustive query takes less than about 0.1 s on one core (docs/scale.md).
    static constexpr std::size_t kTwoStageAbove = 20000;

    /// Adds models one by one (constant memory per model: a collection of 10^6 models need not
    /// exist as histograms at once), then finish() packs the index.
    class Builder {
    public:
        Builder(views::Codebook codebook, std::string method, int simplify, int views);
        /// One model (V histograms of the codebook's words). InputError naming it on bad input.
        void add(const std::string& name, const std::string& cls, const std::vector<views::Histogram>& views);
        std::size_t size() const;
        /// The index; with `summary` the first pass is trained and every model coded (threads: <= 0 every
        /// core).
        CollectionIndex finish(const SummaryOptions* summary = nullptr, int threads = 0);

    private:
        struct Parts;
        std::shared_ptr<Parts> parts_;
    };

    CollectionIndex() = default;
    /// Packs `models` (each V histograms of the codebook's words; names and classes alike long)
    /// with a first pass of the default options. `method` and `simplify` say how a query mesh is
    /// to be processed (the run's settings). InputError on inconsistent input or counts beyond 16 bits.
    static CollectionIndex build(const std::vector<std::string>& names,
                                 const std::vector<std::string>& classes,
                                 const std::vector<std::vector<views::Histogram>>& models,
                                 views::Codebook codebook, const std::string& method, int simplify = 0);
    /// Reads and writes the file format above (InputError naming the file and the problem). With
    /// `map` (POSIX systems) the model bytes stay in the file, memory-mapped: a query reads only the
    /// models it scores (each checked the first time), the rest is read into memory.
    static CollectionIndex load(const std::string& path, bool map = false);
    void save(const std::string& path) const;

    std::size_t size() const { return names_.size(); }
    int views() const { return views_; }
    const std::vector<std::string>& names() const { return names_; }
    const std::vector<std::string>& classes() const { return classes_; }
    const views::Codebook& codebook() const { return codebook_; }
    const std::string& method() const { return method_; }
    int simplify() const { return simplify_; }
    /// Bytes of the packed histograms (offsets and model bytes).
    std::size_t bytes() const {
        return offsets_.size() * sizeof(std::uint64_t) +
               static_cast<std::size_t>(offsets_.empty() ? 0 : offsets_.back());
    }
    /// Whether the model bytes are memory-mapped from the file (load() with `map`).
    bool mapped() const { return mapped_ != nullptr; }
    /// The first pass (untrained if the index has none).
    const SummarySearch& first_pass() const { return first_; }
    /// The V histograms of model `m`, unpacked.
    std::vector<views::Histogram> histograms(std::size_t m) const;

    /// Clock-matching distance of `query` (V histograms) to every model. threads <= 0: every core.
    /// `self` as SearchOptions::self.
    std::vector<float> distances(const std::vector<views::Histogram>& query, int threads = 0,
                                 std::ptrdiff_t self = -1) const;
    /// The same for the models `models` only (in that order).
    std::vector<float> distances(const std::vector<views::Histogram>& query,
                                 const std::vector<std::uint32_t>& models, int threads = 0,
                                 std::ptrdiff_t self = -1) const;
    /// The `k` nearest models by exhaustive clock matching, nearest first (ties: lower model index first).
    std::vector<IndexMatch> top(const std::vector<views::Histogram>& query, std::size_t k,
                                int threads = 0) const;

    /// Whether search() with these options uses the first pass: not `exact`, the index has one,
    /// and it holds more than kTwoStageAbove models or `candidates` was given.
    bool two_stage(const SearchOptions& options) const;
    /// The default candidate count of a top-k query over N models: the largest of kCandidatesMin,
    /// kCandidatesPerK x k and N / kCandidatesShare, at most N (recall against the candidate count
    /// at 10^5 and 10^6 models: docs/scale.md).
    static constexpr std::size_t kCandidatesMin = 1000, kCandidatesPerK = 40, kCandidatesShare = 200;
    /// That rule in words, for help texts ("max(1000, 40 K, N / 200)").
    static std::string default_candidates_rule();
    /// The first pass's candidates for a top-`k` query when none are given (the rule above).
    std::size_t default_candidates(std::size_t k) const;
    /// The `k` nearest models: two_stage() ? the exact distances of the first pass's candidates :
    /// top(); nearest first, ties by lower model index, distances exact either way.
    std::vector<IndexMatch> search(const std::vector<views::Histogram>& query, std::size_t k,
                                   const SearchOptions& options = {}) const;
    /// The first pass's code of a query (first_pass().dims() bytes). InputError without a first pass.
    std::vector<std::int8_t> code(const std::vector<views::Histogram>& query) const;

private:
    int views_ = 0;
    std::vector<std::string> names_, classes_;
    views::Codebook codebook_;
    std::string method_;
    int simplify_ = 0;
    std::vector<std::uint64_t> offsets_;          // N + 1 byte offsets
    std::vector<std::uint8_t> data_;              // the models' bytes, unless mapped
    std::shared_ptr<const std::uint8_t> mapped_;  // or in the mapped file (unmapped with the last copy)
    std::shared_ptr<std::atomic<std::uint8_t>[]> checked_;  // per mapped model: checked already
    /// The bytes of model m (a mapped model checked on first use: InputError if damaged).
    const std::uint8_t* model_bytes(std::size_t m) const;
    /// distances(); with `keep` > 0 only the `keep` smallest are certain: a model found farther
    /// than them early in its clock matching is given up (+infinity).
    std::vector<float> scores(const std::vector<views::Histogram>& query,
                              const std::vector<std::uint32_t>& models, int threads, std::ptrdiff_t self,
                              std::size_t keep) const;
    SummarySearch first_;
    std::vector<int> orbit_of_view_;
    int orbit_count_ = 0;
    void train_first_pass(const SummaryOptions& options, int threads);
    friend class IndexFile;
};

/// The index of one method's folder of a retrieval run (`retrieve` or a sharded run): its
/// models.csv (order, classes), descriptors/NAME.cfvd (histograms) and codebook.bin. InputError
/// naming what is missing.
CollectionIndex index_method_folder(const std::string& folder, const std::string& method, int simplify = 0);
/// The index of the models `names` (classes alike long) of a method folder: descriptors/NAME.cfvd
/// and codebook.bin, in that order, with the default first pass. threads <= 0: every core.
CollectionIndex index_descriptors(const std::string& folder, const std::vector<std::string>& names,
                                  const std::vector<std::string>& classes, const std::string& method,
                                  int simplify = 0, int threads = 0);

}  // namespace canonform::retrieval
