// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the first pass of a two-stage query over an indexed collection (collection_index.h):
// a short code per model, unchanged by the 24 rotations clock matching tries, whose distances to a
// query's code rank the collection roughly as clock matching does. The nearest codes are the
// candidates; clock matching then ranks them exactly (collection_index.h).
//
// References: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape
// retrieval using Clock Matching and Bag-of-Features", Machine Vision and Applications 24, 2013
// (the views, the rotations, the distance); N. Halko, P.-G. Martinsson, J. A. Tropp, "Finding
// structure with randomness", SIAM Review 53(2), 2011 (randomised subspace iteration, Alg. 4.4);
// G. H. Golub, C. F. Van Loan, "Matrix Computations", 4th ed., Sec. 8.5 (cyclic Jacobi
// eigenvalue method); H. Jegou, M. Douze, C. Schmid, "Product quantization for nearest neighbor
// search", IEEE TPAMI 33(1), 2011 (a compressed first pass reranked by exact distances).
//
// Summary (ours): the 24 cube rotations permute the 66 views within four orbits (6, 12, 24 and 24
// views, found from views::rotation_view_maps()). Summing each orbit's view histograms gives four
// histograms that no rotation changes: s = (sum over O_1 of h_i, ..., sum over O_4 of h_i), 4W
// values for a codebook of W words (one sum over all 66 views with `orbits` off). Each value is
// square-rooted (the Hellinger map: frequent words do not drown the rest) and s is scaled to unit
// length. The view-to-view correspondence of clock matching is lost; what is kept is which words
// a model shows in which kind of view.
//
// Projection: the principal axes of the summaries of a sample of models (at most `sample`, evenly
// spaced in model order), centred on their mean: with X the centred sample (rows), L = dims + 16
// columns and a +-1 matrix Omega drawn from a seeded splitmix64 stream, Y = X Omega; `iterations`
// times Z = orth(X^T orth(Y)), Y = X Z; then P = orth(X^T orth(Y)) (orth: modified Gram-Schmidt,
// twice). The eigenvectors V of (X P)^T (X P), by cyclic Jacobi sweeps (rotation of (p, q):
// tau = (a_qq - a_pp) / 2a_pq, t = sign(tau) / (|tau| + sqrt(1 + tau^2)), c = 1 / sqrt(1 + t^2),
// s = t c) until the off-diagonal part is below 1e-15 of the whole, rotate P onto the axes; the
// `dims` of largest eigenvalue (ties: lower index) are kept.
//
// Codes: a summary's coordinates on the axes, less the mean's, times one scale (127 / (5 sigma_1),
// sigma_1 the spread of the sample along the first axis), rounded half away from zero and clamped
// to [-127, 127]: `dims` signed bytes per model. The first pass ranks by the squared Euclidean
// distance between codes in exact integer arithmetic, ties by the lower model index. The codes are
// held split: every model's first prefix_dims() bytes (the axes of largest spread) together, the
// rest apart; a query computes the prefix distance of every model and adds the rest's only where
// the prefix distance is below the bound of the candidates held (a whole distance is at least its
// prefix's): the same candidates as whole distances everywhere, from fewer bytes read.
//
// Portability: training uses only +, -, *, / and sqrt in double, in loops of fixed order (no BLAS,
// whose blocking follows the CPU); a code is a float sum in a fixed order; distances are integers
// (the AVX-512 and AVX2 clones of the loops give the same sums). Codes and candidates are the same
// bits on every x86-64 CPU and for every thread count.
#pragma once

#include "canonform/views/bag_of_features.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace canonform::retrieval {

/// How the first pass is made.
struct SummaryOptions {
    int dims = 128;           ///< bytes per model: projected dimensions (a multiple of 16, 16 to 256)
    bool orbits = true;       ///< one histogram per rotation orbit of the views (else one over all views)
    bool sqrt_counts = true;  ///< square roots of the summed counts (the Hellinger map)
    int sample = 8192;        ///< models the axes are trained on (evenly spaced; all if fewer)
    int iterations = 3;       ///< subspace iterations of the range finder
    std::uint64_t seed = 1;   ///< seed of Omega
};

/// A model's summary before projection: non-zero coordinates, indices ascending.
struct Summary {
    std::vector<std::uint32_t> index;
    std::vector<double> value;
};

/// The orbit of each of the V views under the rotation maps (orbits numbered by their first
/// view), and their count. InputError if the maps do not fit V views.
std::vector<int> view_orbits(const std::vector<std::vector<int>>& maps, int views, int* count = nullptr);

/// The trained projection and the codes of a collection.
class SummarySearch {
public:
    SummarySearch() = default;

    /// Trains the axes on `sample` (summaries of `summary_dims` coordinates). `threads` <= 0:
    /// every core. InputError if the sample is empty or the options are out of range.
    static SummarySearch train(const std::vector<Summary>& sample, std::uint32_t summary_dims,
                               const SummaryOptions& options, int threads = 0);
    /// Rebuilds a trained search from its parts (the index file): the options, the orbit layout,
    /// the axes (summary_dims x dims, row-major), the centring offsets (dims) and the scale.
    static SummarySearch from_parts(const SummaryOptions& options, std::uint32_t summary_dims,
                                    std::vector<float> axes, std::vector<float> offset, float scale);

    bool trained() const { return dims_ > 0; }
    int dims() const { return dims_; }
    std::uint32_t summary_dims() const { return summary_dims_; }
    const SummaryOptions& options() const { return options_; }
    const std::vector<float>& axes() const { return axes_; }
    const std::vector<float>& offset() const { return offset_; }
    float scale() const { return scale_; }

    /// The summary of one model's V view histograms (orbits: view_orbits() of the same maps).
    static Summary summarise(const std::vector<views::Histogram>& views,
                             const std::vector<int>& orbit_of_view, int orbit_count, int words,
                             const SummaryOptions& options);
    /// The code of a summary: dims() signed bytes written to `out`.
    void encode(const Summary& s, std::int8_t* out) const;

    /// The codes of the collection (size N x dims(), model after model), and their count.
    void set_codes(std::vector<std::int8_t> codes);
    /// The same codes already in the layout nearest() reads (N x dims() bytes: every model's first
    /// prefix_dims() bytes, model after model, then the other bytes of every model), as
    /// put_split() writes them: no second copy of the codes is held.
    void set_split_codes(std::vector<std::int8_t> split);
    /// Writes model m's code (dims bytes) into the split layout of n models.
    static void put_split(std::int8_t* split, std::size_t n, int dims, std::size_t m,
                          const std::int8_t* code);
    std::vector<std::int8_t> codes() const;
    std::size_t size() const { return size_; }
    std::size_t bytes() const { return codes_.size() + axes_.size() * sizeof(float); }
    /// The leading dimensions whose distances nearest() computes for every model.
    static int prefix_dims(int dims) { return std::max(16, dims / 64 * 16); }

    /// The `count` models whose codes are nearest to `query` (dims() bytes), nearest first, ties
    /// by the lower model index. `threads` <= 0: every core; the answer does not depend on it.
    std::vector<std::uint32_t> nearest(const std::int8_t* query, std::size_t count, int threads = 1) const;

private:
    SummaryOptions options_;
    int dims_ = 0;
    std::uint32_t summary_dims_ = 0;
    std::vector<float> axes_;    // summary_dims x dims
    std::vector<float> offset_;  // dims: the mean summary's coordinates
    float scale_ = 1;
    std::size_t size_ = 0;
    // The codes split: the first prefix_dims() bytes of every model (N x P), then the rest of
    // every model (N x (dims - P)): a query reads the prefixes of all and the rest of few.
    std::vector<std::int8_t> codes_;
};

}  // namespace canonform::retrieval
