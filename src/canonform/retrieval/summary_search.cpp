// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/summary_search.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/common/parallel.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

namespace canonform::retrieval {

namespace {

/// splitmix64: the +-1 entries of Omega, the same on every platform.
std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ULL;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
}

/// A dense row-major matrix of doubles.
struct Dense {
    std::size_t rows = 0, cols = 0;
    std::vector<double> v;
    Dense() = default;
    Dense(std::size_t r, std::size_t c) : rows(r), cols(c), v(r * c, 0.0) {}
    double* row(std::size_t r) { return v.data() + r * cols; }
    const double* row(std::size_t r) const { return v.data() + r * cols; }
};

/// The sample as sparse rows and as sparse columns (for X^T products).
struct Sparse {
    std::size_t rows = 0, cols = 0;
    std::vector<std::size_t> row_start;  // rows + 1
    std::vector<std::uint32_t> row_index;
    std::vector<double> row_value;
    std::vector<std::size_t> col_start;    // cols + 1
    std::vector<std::uint32_t> col_index;  // the row of each entry, ascending within a column
    std::vector<double> col_value;
};

Sparse make_sparse(const std::vector<Summary>& sample, std::uint32_t dims) {
    Sparse x;
    x.rows = sample.size();
    x.cols = dims;
    x.row_start.push_back(0);
    std::vector<std::size_t> per_col(dims + 1, 0);
    for (const Summary& s : sample) {
        for (std::size_t k = 0; k < s.index.size(); ++k) {
            if (s.index[k] >= dims || (k > 0 && s.index[k] <= s.index[k - 1]) || !std::isfinite(s.value[k]))
                throw InputError(
                    "Summary search: a summary with an index out of range, out of order or a "
                    "non-finite value");
            x.row_index.push_back(s.index[k]);
            x.row_value.push_back(s.value[k]);
            ++per_col[s.index[k] + 1];
        }
        x.row_start.push_back(x.row_index.size());
    }
    x.col_start.assign(dims + 1, 0);
    for (std::uint32_t j = 0; j < dims; ++j) x.col_start[j + 1] = x.col_start[j] + per_col[j + 1];
    x.col_index.resize(x.row_index.size());
    x.col_value.resize(x.row_index.size());
    std::vector<std::size_t> at(x.col_start.begin(), x.col_start.end() - 1);
    for (std::size_t r = 0; r < x.rows; ++r)
        for (std::size_t e = x.row_start[r]; e < x.row_start[r + 1]; ++e) {
            const std::size_t p = at[x.row_index[e]]++;
            x.col_index[p] = static_cast<std::uint32_t>(r);
            x.col_value[p] = x.row_value[e];
        }
    return x;
}

/// (X - 1 mu^T) B for B (cols x L): row r = sum over its entries of v B[j] - mu^T B.
Dense times(const Sparse& x, const std::vector<double>& mu, const Dense& b, int threads) {
    const std::size_t L = b.cols;
    std::vector<double> mub(L, 0.0);
    for (std::size_t j = 0; j < x.cols; ++j)
        for (std::size_t l = 0; l < L; ++l) mub[l] += mu[j] * b.row(j)[l];
    Dense y(x.rows, L);
    ParallelOptions par;
    par.threads = threads;
    par.grain = 64;
    parallel_for(
        static_cast<std::ptrdiff_t>(x.rows),
        [&](std::ptrdiff_t r, int) {
            double* out = y.row(static_cast<std::size_t>(r));
            for (std::size_t e = x.row_start[static_cast<std::size_t>(r)];
                 e < x.row_start[static_cast<std::size_t>(r) + 1]; ++e) {
                const double v = x.row_value[e];
                const double* br = b.row(x.row_index[e]);
                for (std::size_t l = 0; l < L; ++l) out[l] += v * br[l];
            }
            for (std::size_t l = 0; l < L; ++l) out[l] -= mub[l];
        },
        par);
    return y;
}

/// (X - 1 mu^T)^T Q for Q (rows x L): row j = sum over column j's entries of v Q[r] - mu_j 1^T Q.
Dense transposed_times(const Sparse& x, const std::vector<double>& mu, const Dense& q, int threads) {
    const std::size_t L = q.cols;
    std::vector<double> colsum(L, 0.0);
    for (std::size_t r = 0; r < q.rows; ++r)
        for (std::size_t l = 0; l < L; ++l) colsum[l] += q.row(r)[l];
    Dense z(x.cols, L);
    ParallelOptions par;
    par.threads = threads;
    par.grain = 64;
    parallel_for(
        static_cast<std::ptrdiff_t>(x.cols),
        [&](std::ptrdiff_t jj, int) {
            const auto j = static_cast<std::size_t>(jj);
            double* out = z.row(j);
            for (std::size_t e = x.col_start[j]; e < x.col_start[j + 1]; ++e) {
                const double v = x.col_value[e];
                const double* qr = q.row(x.col_index[e]);
                for (std::size_t l = 0; l < L; ++l) out[l] += v * qr[l];
            }
            for (std::size_t l = 0; l < L; ++l) out[l] -= mu[j] * colsum[l];
        },
        par);
    return z;
}

/// Orthonormal columns by modified Gram-Schmidt, twice; a column that vanishes becomes zero.
void orthonormalise(Dense& a) {
    for (std::size_t c = 0; c < a.cols; ++c) {
        double before = 0;
        for (std::size_t i = 0; i < a.rows; ++i) before += a.row(i)[c] * a.row(i)[c];
        for (int pass = 0; pass < 2; ++pass)
            for (std::size_t p = 0; p < c; ++p) {
                double r = 0;
                for (std::size_t i = 0; i < a.rows; ++i) r += a.row(i)[c] * a.row(i)[p];
                for (std::size_t i = 0; i < a.rows; ++i) a.row(i)[c] -= r * a.row(i)[p];
            }
        double after = 0;
        for (std::size_t i = 0; i < a.rows; ++i) after += a.row(i)[c] * a.row(i)[c];
        const double scale = after > 1e-24 * before && after > 0 ? 1.0 / std::sqrt(after) : 0.0;
        for (std::size_t i = 0; i < a.rows; ++i) a.row(i)[c] *= scale;
    }
}

/// Eigenvalues (diagonal of the result) and eigenvectors (columns of `vectors`) of the symmetric
/// matrix `a` by cyclic Jacobi sweeps (see the header).
std::vector<double> jacobi(Dense a, Dense& vectors) {
    const std::size_t n = a.rows;
    vectors = Dense(n, n);
    for (std::size_t i = 0; i < n; ++i) vectors.row(i)[i] = 1.0;
    auto at = [&](std::size_t i, std::size_t j) -> double& { return a.row(i)[j]; };
    double total = 0;
    for (double v : a.v) total += v * v;
    for (int sweep = 0; sweep < 100; ++sweep) {
        double off = 0;
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                if (i != j) off += at(i, j) * at(i, j);
        if (off <= 1e-30 * total) break;
        for (std::size_t p = 0; p + 1 < n; ++p)
            for (std::size_t q = p + 1; q < n; ++q) {
                const double apq = at(p, q);
                if (apq == 0) continue;
                const double tau = (at(q, q) - at(p, p)) / (2 * apq);
                const double t = std::abs(tau) > 1e150
                                     ? 0.5 / tau
                                     : (tau >= 0 ? 1.0 : -1.0) / (std::abs(tau) + std::sqrt(1 + tau * tau));
                const double c = 1 / std::sqrt(1 + t * t), s = t * c;
                at(p, p) -= t * apq;
                at(q, q) += t * apq;
                at(p, q) = at(q, p) = 0;
                for (std::size_t r = 0; r < n; ++r) {
                    if (r == p || r == q) continue;
                    const double arp = at(r, p), arq = at(r, q);
                    at(r, p) = at(p, r) = c * arp - s * arq;
                    at(r, q) = at(q, r) = s * arp + c * arq;
                }
                for (std::size_t r = 0; r < n; ++r) {
                    const double vrp = vectors.row(r)[p], vrq = vectors.row(r)[q];
                    vectors.row(r)[p] = c * vrp - s * vrq;
                    vectors.row(r)[q] = s * vrp + c * vrq;
                }
            }
    }
    std::vector<double> values(n);
    for (std::size_t i = 0; i < n; ++i) values[i] = at(i, i);
    return values;
}

constexpr int kMaxDims = 256;  // SummaryOptions::dims at most

/// The squared distance of D code bytes at `c` to the query's (widened to 16 bits, in registers:
/// the restrict qualifiers tell that no write moves them) - an integer sum, the same in every clone.
template <int D>
inline std::uint32_t squared_distance(const std::int8_t* __restrict c, const std::int16_t* __restrict q,
                                      int dims) {
    const int n = D > 0 ? D : dims;
    std::int32_t s = 0;
    for (int k = 0; k < n; ++k) {
        const auto d = static_cast<std::int16_t>(q[k] - c[k]);  // |d| <= 255
        s += static_cast<std::int32_t>(d) * static_cast<std::int32_t>(d);
    }
    return static_cast<std::uint32_t>(s);
}

template <int D>
inline void prefix_distances_of(const std::int8_t* __restrict codes, std::size_t count,
                                const std::int16_t* __restrict q, int dims, std::uint32_t* __restrict out) {
    const std::size_t stride = static_cast<std::size_t>(D > 0 ? D : dims);
    for (std::size_t m = 0; m < count; ++m) out[m] = squared_distance<D>(codes + m * stride, q, dims);
}

/// Squared distances of the query code's first `dims` bytes to `count` codes of `dims` bytes
/// stored one after another.
CANONFORM_CLONES_AVX512 void prefix_distances(const std::int8_t* codes, std::size_t count, int dims,
                                              const std::int8_t* query, std::uint32_t* out) {
    std::int16_t q[kMaxDims];
    for (int k = 0; k < dims; ++k) q[k] = query[k];
    switch (dims) {
        case 16:
            return prefix_distances_of<16>(codes, count, q, dims, out);
        case 32:
            return prefix_distances_of<32>(codes, count, q, dims, out);
        case 64:
            return prefix_distances_of<64>(codes, count, q, dims, out);
        default:
            return prefix_distances_of<0>(codes, count, q, dims, out);
    }
}

template <int D>
inline void add_rest_of(const std::int8_t* __restrict rest, const std::uint32_t* __restrict models,
                        std::size_t count, const std::int16_t* __restrict q, int dims,
                        std::uint32_t* __restrict out) {
    const std::size_t stride = static_cast<std::size_t>(D > 0 ? D : dims);
    for (std::size_t i = 0; i < count; ++i) {
        if (i + 4 < count) __builtin_prefetch(rest + models[i + 4] * stride);  // a hint only
        out[i] += squared_distance<D>(rest + models[i] * stride, q, dims);
    }
}

/// Adds to out[i] the squared distance of the query's `dims` bytes at `query` to the `dims` bytes
/// of model models[i] in `rest` (a code of `dims` bytes per model).
CANONFORM_CLONES_AVX512 void add_rest(const std::int8_t* rest, const std::uint32_t* models, std::size_t count,
                                      int dims, const std::int8_t* query, std::uint32_t* out) {
    std::int16_t q[kMaxDims];
    for (int k = 0; k < dims; ++k) q[k] = query[k];
    switch (dims) {
        case 32:
            return add_rest_of<32>(rest, models, count, q, dims, out);
        case 48:
            return add_rest_of<48>(rest, models, count, q, dims, out);
        case 64:
            return add_rest_of<64>(rest, models, count, q, dims, out);
        case 96:
            return add_rest_of<96>(rest, models, count, q, dims, out);
        case 192:
            return add_rest_of<192>(rest, models, count, q, dims, out);
        default:
            return add_rest_of<0>(rest, models, count, q, dims, out);
    }
}

}  // namespace

std::vector<int> view_orbits(const std::vector<std::vector<int>>& maps, int views, int* count) {
    std::vector<int> parent(static_cast<std::size_t>(views));
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int i) {
        while (parent[static_cast<std::size_t>(i)] != i) i = parent[static_cast<std::size_t>(i)];
        return i;
    };
    for (const auto& m : maps) {
        if (m.size() != static_cast<std::size_t>(views))
            throw InputError("Summary search: rotation maps of " + std::to_string(m.size()) + " views for " +
                             std::to_string(views) + " views");
        for (int i = 0; i < views; ++i) {
            const int j = m[static_cast<std::size_t>(i)];
            if (j < 0 || j >= views)
                throw InputError("Summary search: a rotation map names a view out of range");
            const int a = find(i), b = find(j);
            if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
        }
    }
    std::vector<int> orbit(static_cast<std::size_t>(views), -1),
        id_of_root(static_cast<std::size_t>(views), -1);
    int n = 0;
    for (int i = 0; i < views; ++i) {
        const int r = find(i);
        if (id_of_root[static_cast<std::size_t>(r)] < 0) id_of_root[static_cast<std::size_t>(r)] = n++;
        orbit[static_cast<std::size_t>(i)] = id_of_root[static_cast<std::size_t>(r)];
    }
    if (count) *count = n;
    return orbit;
}

Summary SummarySearch::summarise(const std::vector<views::Histogram>& views,
                                 const std::vector<int>& orbit_of_view, int orbit_count, int words,
                                 const SummaryOptions& options) {
    if (orbit_of_view.size() != views.size())
        throw InputError("Summary search: " + std::to_string(views.size()) + " views, orbits for " +
                         std::to_string(orbit_of_view.size()));
    // Entries (coordinate, count) of every view, then merged by coordinate: counts are integers,
    // so the sums are exact whatever the order.
    std::vector<std::pair<std::uint32_t, double>> e;
    std::size_t n = 0;
    for (const auto& h : views) n += h.size();
    e.reserve(n);
    for (std::size_t i = 0; i < views.size(); ++i) {
        const auto base = static_cast<std::uint32_t>(options.orbits ? orbit_of_view[i] * words : 0);
        for (const auto& [w, c] : views[i]) e.emplace_back(base + static_cast<std::uint32_t>(w), c);
    }
    (void)orbit_count;
    std::sort(e.begin(), e.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    Summary s;
    for (const auto& [j, c] : e) {
        if (!s.index.empty() && s.index.back() == j) {
            s.value.back() += c;
        } else {
            s.index.push_back(j);
            s.value.push_back(c);
        }
    }
    if (options.sqrt_counts)
        for (double& v : s.value) v = std::sqrt(v);
    double norm = 0;
    for (double v : s.value) norm += v * v;
    if (norm > 0) {
        const double inv = 1.0 / std::sqrt(norm);
        for (double& v : s.value) v *= inv;
    }
    return s;
}

SummarySearch SummarySearch::train(const std::vector<Summary>& sample, std::uint32_t summary_dims,
                                   const SummaryOptions& o, int threads) {
    if (sample.empty()) throw InputError("Summary search: no models to train the projection on");
    if (o.dims < 16 || o.dims > 256 || o.dims % 16 != 0)
        throw InputError("Summary search: dims " + std::to_string(o.dims) +
                         " (a multiple of 16 from 16 to 256)");
    if (o.iterations < 0 || o.iterations > 20) throw InputError("Summary search: iterations from 0 to 20");
    if (summary_dims == 0) throw InputError("Summary search: summaries of no coordinates");
    const Sparse x = make_sparse(sample, summary_dims);
    const std::size_t S = x.rows, D = summary_dims;
    const std::size_t L = std::min<std::size_t>(static_cast<std::size_t>(o.dims) + 16, D);
    std::vector<double> mu(D, 0.0);
    for (std::size_t r = 0; r < S; ++r)
        for (std::size_t e = x.row_start[r]; e < x.row_start[r + 1]; ++e)
            mu[x.row_index[e]] += x.row_value[e];
    for (double& m : mu) m /= static_cast<double>(S);

    Dense omega(D, L);
    for (std::size_t j = 0; j < D; ++j)
        for (std::size_t l = 0; l < L; ++l)
            omega.row(j)[l] = (splitmix64(o.seed ^ splitmix64(j * L + l)) >> 63) ? -1.0 : 1.0;
    Dense y = times(x, mu, omega, threads);
    for (int it = 0; it < o.iterations; ++it) {
        orthonormalise(y);
        Dense z = transposed_times(x, mu, y, threads);
        orthonormalise(z);
        y = times(x, mu, z, threads);
    }
    orthonormalise(y);
    Dense p = transposed_times(x, mu, y, threads);
    orthonormalise(p);
    // The small eigenproblem of (X P)^T (X P).
    const Dense c = times(x, mu, p, threads);
    Dense m(L, L);
    for (std::size_t a = 0; a < L; ++a)
        for (std::size_t b = a; b < L; ++b) {
            double s = 0;
            for (std::size_t r = 0; r < S; ++r) s += c.row(r)[a] * c.row(r)[b];
            m.row(a)[b] = m.row(b)[a] = s;
        }
    Dense v;
    const std::vector<double> lambda = jacobi(m, v);
    std::vector<std::size_t> order(L);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return lambda[a] > lambda[b]; });

    SummarySearch out;
    out.options_ = o;
    out.dims_ = o.dims;
    out.summary_dims_ = summary_dims;
    const auto dims = static_cast<std::size_t>(o.dims);
    out.axes_.assign(D * dims, 0.f);
    std::vector<double> offset(dims, 0.0);
    for (std::size_t k = 0; k < std::min(dims, L); ++k) {
        const std::size_t col = order[k];
        for (std::size_t j = 0; j < D; ++j) {
            double a = 0;
            for (std::size_t l = 0; l < L; ++l) a += p.row(j)[l] * v.row(l)[col];
            out.axes_[j * dims + k] = static_cast<float>(a);
        }
    }
    // The mean's coordinates, summed as encode() sums a summary's.
    Summary mean;
    for (std::size_t j = 0; j < D; ++j)
        if (mu[j] != 0) {
            mean.index.push_back(static_cast<std::uint32_t>(j));
            mean.value.push_back(mu[j]);
        }
    out.offset_.assign(dims, 0.f);
    out.scale_ = 1.f;
    const double sigma = lambda[order[0]] > 0 ? std::sqrt(lambda[order[0]] / static_cast<double>(S)) : 0.0;
    std::vector<float> raw(dims, 0.f);
    for (std::size_t e = 0; e < mean.index.size(); ++e) {
        const float val = static_cast<float>(mean.value[e]);
        const float* a = out.axes_.data() + static_cast<std::size_t>(mean.index[e]) * dims;
        for (std::size_t k = 0; k < dims; ++k) raw[k] += val * a[k];
    }
    out.offset_ = raw;
    out.scale_ = sigma > 0 ? static_cast<float>(127.0 / (5.0 * sigma)) : 1.f;
    return out;
}

SummarySearch SummarySearch::from_parts(const SummaryOptions& options, std::uint32_t summary_dims,
                                        std::vector<float> axes, std::vector<float> offset, float scale) {
    if (options.dims < 16 || options.dims > 256 || options.dims % 16 != 0 || summary_dims == 0 ||
        axes.size() != static_cast<std::size_t>(summary_dims) * static_cast<std::size_t>(options.dims) ||
        offset.size() != static_cast<std::size_t>(options.dims) || !(scale > 0) || !std::isfinite(scale))
        throw InputError("Summary search: inconsistent parts (dims, axes, offsets or scale)");
    for (float a : axes)
        if (!std::isfinite(a)) throw InputError("Summary search: a non-finite axis value");
    for (float a : offset)
        if (!std::isfinite(a)) throw InputError("Summary search: a non-finite offset");
    SummarySearch s;
    s.options_ = options;
    s.dims_ = options.dims;
    s.summary_dims_ = summary_dims;
    s.axes_ = std::move(axes);
    s.offset_ = std::move(offset);
    s.scale_ = scale;
    return s;
}

void SummarySearch::encode(const Summary& s, std::int8_t* out) const {
    const auto dims = static_cast<std::size_t>(dims_);
    float acc[256] = {};
    for (std::size_t e = 0; e < s.index.size(); ++e) {
        if (s.index[e] >= summary_dims_)
            throw InputError("Summary search: a summary coordinate out of range");
        const float val = static_cast<float>(s.value[e]);
        const float* a = axes_.data() + static_cast<std::size_t>(s.index[e]) * dims;
        for (std::size_t k = 0; k < dims; ++k) acc[k] += val * a[k];
    }
    for (std::size_t k = 0; k < dims; ++k) {
        const float x = (acc[k] - offset_[k]) * scale_;
        // Half away from zero, then clamped; a NaN (cannot come from finite parts) becomes 0.
        const float r = x >= 0 ? std::floor(x + 0.5f) : -std::floor(-x + 0.5f);
        out[k] = static_cast<std::int8_t>(r > 127.f ? 127.f : (r < -127.f ? -127.f : (r == r ? r : 0.f)));
    }
}

namespace {

/// Where model m's prefix and rest lie in the split layout of n codes of `dims` bytes.
struct SplitAt {
    std::size_t prefix, rest, p, r;  // offsets and lengths
};
SplitAt split_at(std::size_t n, int dims, std::size_t m) {
    const auto d = static_cast<std::size_t>(dims),
               p = static_cast<std::size_t>(SummarySearch::prefix_dims(dims));
    return {m * p, n * p + m * (d - p), p, d - p};
}

}  // namespace

void SummarySearch::put_split(std::int8_t* split, std::size_t n, int dims, std::size_t m,
                              const std::int8_t* code) {
    const SplitAt at = split_at(n, dims, m);
    std::memcpy(split + at.prefix, code, at.p);
    std::memcpy(split + at.rest, code + at.p, at.r);
}

void SummarySearch::set_split_codes(std::vector<std::int8_t> split) {
    if (dims_ <= 0 || split.size() % static_cast<std::size_t>(dims_) != 0)
        throw InputError("Summary search: codes that are not whole models of " + std::to_string(dims_) +
                         " bytes");
    size_ = split.size() / static_cast<std::size_t>(dims_);
    codes_ = std::move(split);
}

void SummarySearch::set_codes(std::vector<std::int8_t> codes) {
    if (dims_ <= 0 || codes.size() % static_cast<std::size_t>(dims_) != 0)
        throw InputError("Summary search: codes that are not whole models of " + std::to_string(dims_) +
                         " bytes");
    const std::size_t n = codes.size() / static_cast<std::size_t>(dims_);
    std::vector<std::int8_t> split(codes.size());
    for (std::size_t m = 0; m < n; ++m)
        put_split(split.data(), n, dims_, m, codes.data() + m * static_cast<std::size_t>(dims_));
    set_split_codes(std::move(split));
}

std::vector<std::int8_t> SummarySearch::codes() const {
    const auto d = static_cast<std::size_t>(dims_);
    std::vector<std::int8_t> out(codes_.size());
    for (std::size_t m = 0; m < size_; ++m) {
        const SplitAt at = split_at(size_, dims_, m);
        std::memcpy(out.data() + m * d, codes_.data() + at.prefix, at.p);
        std::memcpy(out.data() + m * d + at.p, codes_.data() + at.rest, at.r);
    }
    return out;
}

std::vector<std::uint32_t> SummarySearch::nearest(const std::int8_t* query, std::size_t count,
                                                  int threads) const {
    const std::size_t n = size();
    count = std::min(count, n);
    if (count == 0) return {};
    // The distances over the first prefix_dims() bytes of every model first (a whole distance is at
    // least its prefix's). An upper bound B of the count-th smallest key (distance, model): the
    // count-th smallest whole key of the seed, the models of smallest prefix distance (at least
    // count of them, found by a histogram), whose count smallest keys are kept. Then per block the
    // other models whose prefix key is at most B get their whole distance, and per worker the keys
    // below its bound are held: when 2 x count are held, the count
    // smallest are kept (nth_element) and the largest of them becomes the bound. A key above B or at
    // or above a bound cannot be among the count smallest (keys are distinct), so the union's
    // smallest are the answer whatever the split; pushing a key costs less than a heap's push and pop.
    constexpr std::size_t kBlock = 4096, kSeedShare = 4;
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    ParallelOptions par;
    par.threads = threads;
    par.grain = 8;
    const int workers = parallel_workers(static_cast<std::ptrdiff_t>(blocks), par);
    const int p = prefix_dims(dims_), r = dims_ - p;
    const std::int8_t* rest = codes_.data() + n * static_cast<std::size_t>(p);
    std::vector<std::uint32_t> prefix(n);
    parallel_for(
        static_cast<std::ptrdiff_t>(blocks),
        [&](std::ptrdiff_t b, int) {
            const std::size_t begin = static_cast<std::size_t>(b) * kBlock, end = std::min(n, begin + kBlock);
            prefix_distances(codes_.data() + begin * static_cast<std::size_t>(p), end - begin, p, query,
                             prefix.data() + begin);
        },
        par);
    auto key_of = [](std::uint32_t d, std::size_t m) {
        return (static_cast<std::uint64_t>(d) << 32) | static_cast<std::uint64_t>(m);
    };
    // The seed: the models in the histogram's first buckets (all of them if count == n), their
    // whole keys computed once here; the blocks below skip them.
    int shift = 0;
    while ((static_cast<std::uint32_t>(p) * 255u * 255u >> shift) >= 65536u) ++shift;
    std::vector<std::uint32_t> histogram(65536);
    for (std::uint32_t d : prefix) ++histogram[d >> shift];
    std::uint32_t last = 0;
    const std::size_t want = std::min(n, kSeedShare * count);
    for (std::size_t held = 0; (held += histogram[last]) < want;) ++last;
    std::vector<std::uint32_t> seed, whole;
    for (std::size_t m = 0; m < n; ++m)
        if ((prefix[m] >> shift) <= last) {
            seed.push_back(static_cast<std::uint32_t>(m));
            whole.push_back(prefix[m]);
        }
    if (r > 0) add_rest(rest, seed.data(), seed.size(), r, query + p, whole.data());
    std::vector<std::uint64_t> keys(seed.size());
    for (std::size_t i = 0; i < seed.size(); ++i) keys[i] = key_of(whole[i], seed[i]);
    std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(count - 1), keys.end());
    keys.resize(count);
    const std::uint64_t bound = keys[count - 1] + 1;  // keys at most B pass
    struct Best {
        std::vector<std::uint64_t> keys;
        std::uint64_t bound;
        std::vector<std::uint32_t> near = std::vector<std::uint32_t>(kBlock),
                                   dn = std::vector<std::uint32_t>(kBlock);
    };
    std::vector<Best> best(static_cast<std::size_t>(workers));
    for (Best& k : best) k.bound = bound;
    parallel_for(
        static_cast<std::ptrdiff_t>(blocks),
        [&](std::ptrdiff_t b, int w) {
            const std::size_t begin = static_cast<std::size_t>(b) * kBlock, end = std::min(n, begin + kBlock);
            Best& k = best[static_cast<std::size_t>(w)];
            std::size_t near = 0;
            for (std::size_t m = begin; m < end; ++m)
                if ((prefix[m] >> shift) > last && key_of(prefix[m], m) < k.bound) {
                    k.near[near] = static_cast<std::uint32_t>(m);
                    k.dn[near++] = prefix[m];
                }
            if (r > 0) add_rest(rest, k.near.data(), near, r, query + p, k.dn.data());
            for (std::size_t i = 0; i < near; ++i) {
                const std::uint64_t key = key_of(k.dn[i], k.near[i]);
                if (key >= k.bound) continue;
                k.keys.push_back(key);
                if (k.keys.size() >= 2 * count) {
                    const auto nth = k.keys.begin() + static_cast<std::ptrdiff_t>(count - 1);
                    std::nth_element(k.keys.begin(), nth, k.keys.end());
                    k.bound = *nth;
                    k.keys.resize(count);
                }
            }
        },
        par);
    for (const Best& k : best) keys.insert(keys.end(), k.keys.begin(), k.keys.end());
    if (keys.size() > count) {
        std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(count - 1), keys.end());
        keys.resize(count);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<std::uint32_t> out;
    out.reserve(keys.size());
    for (std::uint64_t k : keys) out.push_back(static_cast<std::uint32_t>(k & 0xFFFFFFFFu));
    return out;
}

}  // namespace canonform::retrieval
