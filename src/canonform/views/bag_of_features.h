// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: bag-of-features view histograms and the clock-matching distance of CM-BOF.
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape retrieval
// using Clock Matching and Bag-of-Features", Machine Vision and Applications 24, 2013 (Sec. 3.3-3.4);
// Pickup et al., Pattern Recognition 2015 (CM-BOF applied to canonical forms).
//
//   view distance   D(h1, h2) = 1 - sum_k min(h1_k, h2_k) / max(sum_k h1_k, sum_k h2_k)
//   clock matching  D(A, B)   = min over rotations r of sum_i D(a_i, b_{maps[r][i]})
//
// where maps[r][i] is the view of B onto which rotation r (one of the 24 rotations of the cube)
// maps view i of A. The empty cases (a blank view has no keypoints, so an empty histogram):
// both empty -> 0 (two blank views agree), exactly one empty -> 1 (maximal). D is in [0, 1] for
// non-negative histograms, symmetric, and 0 for equal histograms.
//
// Histograms are sparse: (word, count) pairs sorted by strictly increasing word, counts > 0.
// The functions taking whole models validate that (InputError); view_distance() does not (hot path).
//
// distance_matrix() computes D(models[i], models[j]) for i < j and mirrors it; the result is the
// true clock-matching distance in both triangles whenever the set of maps is closed under
// inversion (true for the 24 cube rotations), which makes D symmetric. Per model pair it evaluates
// each distinct (view i of A, view j of B) pair used by any rotation once: the intersection summed
// in float over B's entries in order, D from it and the totals in double, each rotation's sum over
// the views in order. One pass over B's view j serves every view of A it meets (for the cube
// rotations, j's orbit), 8 pairs to a vector instruction (cost ~ #views of B x their non-zeros x
// the orbits' lanes / 8).
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <utility>
#include <vector>

namespace canonform::views {

/// Sparse histogram of one view: (word, count), sorted by strictly increasing word, counts > 0.
using Histogram = std::vector<std::pair<int, float>>;

/// Histogram of word indices (each >= 0): counts of each distinct word. Throws InputError on a
/// negative index. An empty input gives an empty histogram.
Histogram histogram(const std::vector<int>& words);

/// The view distance D(a, b) above, in [0, 1]; empty cases as documented. Precondition: both
/// sorted by word with positive counts (not checked here).
double view_distance(const Histogram& a, const Histogram& b);

/// Clock-matching distance min_r sum_i D(a[i], b[maps[r][i]]). maps: R x V (R >= 1), every row a
/// list of V view indices in [0, V) with V = a.size() = b.size(). Throws InputError on a shape
/// mismatch, an index out of range or a malformed histogram.
double clock_matching_distance(const std::vector<Histogram>& a, const std::vector<Histogram>& b,
                               const std::vector<std::vector<int>>& maps);

/// N x N matrix of clock-matching distances between models (each V histograms): symmetric (upper
/// triangle computed, mirrored), zero diagonal. threads <= 0: every hardware thread (thread_count()).
/// Rows are handed out dynamically; the result does not depend on the thread count.
/// Throws InputError like clock_matching_distance().
Eigen::MatrixXf distance_matrix(const std::vector<std::vector<Histogram>>& models,
                                const std::vector<std::vector<int>>& maps, int threads = 0);

/// Rows [row_begin, row_end) of distance_matrix()'s upper triangle, as a (row_end - row_begin) x N
/// block: entry (r - row_begin, c) = D(models[r], models[c]) for c > r, 0 for c <= r - the same
/// floats as distance_matrix() (a row block of a sharded run; mirror the blocks to get the matrix).
/// Throws InputError like distance_matrix() and on a row range outside [0, N].
Eigen::MatrixXf distance_rows(const std::vector<std::vector<Histogram>>& models,
                              const std::vector<std::vector<int>>& maps, std::size_t row_begin,
                              std::size_t row_end, int threads = 0);

}  // namespace canonform::views
