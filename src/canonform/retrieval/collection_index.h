// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: an indexed collection - the bag-of-features histograms of a retrieval run packed for
// queries: the K nearest models of a query model by exact clock matching over the 66 views.
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape
// retrieval using Clock Matching and Bag-of-Features", Machine Vision and Applications 24, 2013
// (Sec. 3.4, clock matching); the distance is bag_of_features.h's, computed differently:
//
//   D(Q, M) = min over rotations r of sum_i d(q_i, m_{maps[r][i]}),
//   d(a, b) = 1 - sum_w min(a_w, b_w) / max(sum a, sum b)   (0 if both empty)
//
// Departures (storage and order of work only; the values are those of views::distance_matrix()):
// - Counts are integers (keypoints per word), stored as 16-bit (word, count) pairs: 4 bytes per
//   non-zero instead of 8; a collection whose codebook has more than 65535 words or a view with
//   more than 65535 keypoints is refused (InputError).
// - Per model, the intersections of all 66 query views with each model view are accumulated at
//   once, word by word, from the query's histograms transposed (word -> 66 counts): exact integer
//   sums (the same values as the float sums of distance_matrix()), in SIMD lanes; then d() and
//   the rotation sums in double in the same order as distance_matrix(), so that D(Q, M) is the
//   float of the matrix (up to the order of the two models: the matrix computes D(A, B) for A
//   before B, equal to D(B, A) up to the last bit of the double sum).
// - Models are scored in parallel (parallel_for), the K smallest kept (ties by model order).
//
// File format (little endian, written atomically):
//   "CFCI", u32 version (1), u32 models N, u32 views V, u32 words W,
//   u32 length + bytes: the method (MethodSpec::to_string()), i32 simplify,
//   N x (u32 length + name, u32 length + class),
//   W x 128 f32 codebook words,
//   (N*V + 1) x u64 entry offsets, then the entries: u16 word, u16 count.
#pragma once

#include "canonform/views/bag_of_features.h"
#include "canonform/views/codebook.h"

#include <cstdint>
#include <string>
#include <vector>

namespace canonform::retrieval {

/// One answer of a query.
struct IndexMatch {
    std::size_t model = 0;  ///< index in the collection
    std::string name, cls;
    float distance = 0;
};

/// The histograms of a collection, packed for queries.
class CollectionIndex {
public:
    CollectionIndex() = default;
    /// Packs `models` (each V histograms of the codebook's words; names and classes alike long).
    /// `method` and `simplify` say how a query mesh is to be processed (the run's settings).
    /// InputError on inconsistent input or counts beyond 16 bits.
    static CollectionIndex build(const std::vector<std::string>& names, const std::vector<std::string>& classes,
                                 const std::vector<std::vector<views::Histogram>>& models, views::Codebook codebook,
                                 const std::string& method, int simplify = 0);
    /// Reads and writes the file format above (InputError naming the file and the problem).
    static CollectionIndex load(const std::string& path);
    void save(const std::string& path) const;

    std::size_t size() const { return names_.size(); }
    int views() const { return views_; }
    const std::vector<std::string>& names() const { return names_; }
    const std::vector<std::string>& classes() const { return classes_; }
    const views::Codebook& codebook() const { return codebook_; }
    const std::string& method() const { return method_; }
    int simplify() const { return simplify_; }
    /// Bytes of the packed histograms (offsets and entries).
    std::size_t bytes() const { return offsets_.size() * sizeof(std::uint64_t) + entries_.size() * sizeof(std::uint16_t); }

    /// Clock-matching distance of `query` (V histograms) to every model. threads <= 0: every core.
    std::vector<float> distances(const std::vector<views::Histogram>& query, int threads = 0) const;
    /// The `k` nearest models, nearest first (ties: lower model index first).
    std::vector<IndexMatch> top(const std::vector<views::Histogram>& query, std::size_t k, int threads = 0) const;

private:
    int views_ = 0;
    std::vector<std::string> names_, classes_;
    views::Codebook codebook_;
    std::string method_;
    int simplify_ = 0;
    std::vector<std::uint64_t> offsets_;  // N*V + 1
    std::vector<std::uint16_t> entries_;  // pairs (word, count)
};

/// The index of one method's folder of a retrieval run (`retrieve` or a sharded run): its
/// models.csv (order, classes), descriptors/NAME.cfvd (histograms) and codebook.bin. InputError
/// naming what is missing.
CollectionIndex index_method_folder(const std::string& folder, const std::string& method, int simplify = 0);

}  // namespace canonform::retrieval
