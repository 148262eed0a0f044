// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/pose_normalization.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/views/pose_cost.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>

namespace canonform::views {

namespace {

void validate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
    if (V.cols() != 3 || V.rows() < 3)
        throw InputError("pose normalisation needs a #V x 3 vertex matrix with at least 3 vertices");
    if (F.rows() == 0 || F.cols() != 3)
        throw InputError("pose normalisation needs a mesh with faces (#F x 3)");
    if (!V.allFinite()) throw InputError("the mesh has non-finite vertex coordinates");
    if (F.minCoeff() < 0 || F.maxCoeff() >= V.rows()) throw InputError("a face index is out of range");
}

// Area vectors (area x unit normal) as columns, 3 x #F.
Eigen::Matrix3Xd area_vectors(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F) {
    Eigen::Matrix3Xd A(3, F.rows());
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const Eigen::Vector3d p0 = X.row(F(f, 0)).transpose();
        const Eigen::Vector3d p1 = X.row(F(f, 1)).transpose();
        const Eigen::Vector3d p2 = X.row(F(f, 2)).transpose();
        A.col(f) = 0.5 * (p1 - p0).cross(p2 - p0);
    }
    return A;
}

// The rotation of the unnormalised quaternion (1, x/2): angle 2 atan(|x| / 2) ~ |x| about x / |x|.
// Only +, -, * and /, which IEEE 754 rounds the same on every x86-64 CPU (libm's sin and cos are
// dispatched at run time to FMA code on CPUs that have it and differ from the SSE2 code in the
// last bit for about 1 argument in 1500).
Eigen::Matrix3d small_rotation(const Eigen::Vector3d& x) {
    const double w = 1.0, a = 0.5 * x[0], b = 0.5 * x[1], c = 0.5 * x[2];
    const double s = 1.0 / (w * w + a * a + b * b + c * c);
    Eigen::Matrix3d R;
    R << 1.0 - 2.0 * s * (b * b + c * c), 2.0 * s * (a * b - c * w), 2.0 * s * (a * c + b * w),
        2.0 * s * (a * b + c * w), 1.0 - 2.0 * s * (a * a + c * c), 2.0 * s * (b * c - a * w),
        2.0 * s * (a * c - b * w), 2.0 * s * (b * c + a * w), 1.0 - 2.0 * s * (a * a + b * b);
    return R;
}

// (1/n) X^T X summed row by row in a fixed order. Eigen's matrix product would split the sum over
// the rows into blocks sized from the L1 cache that CPUID reports (32 KiB on most x86-64 CPUs,
// 48 KiB on recent ones, 64 KiB under qemu64), so its rounding depended on the CPU.
Eigen::Matrix3d covariance(const Eigen::MatrixXd& X) {
    double c00 = 0, c01 = 0, c02 = 0, c11 = 0, c12 = 0, c22 = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
        const double x = X(i, 0), y = X(i, 1), z = X(i, 2);
        c00 += x * x, c01 += x * y, c02 += x * z, c11 += y * y, c12 += y * z, c22 += z * z;
    }
    Eigen::Matrix3d C;
    C << c00, c01, c02, c01, c11, c12, c02, c12, c22;
    return C / static_cast<double>(X.rows());
}

// Makes the frame R (rows = axes) unique: axes by decreasing second moment of X, signs by the
// third moment (two largest |m3| positive, the last one by det +1). See the header, step 4.
Eigen::Matrix3d canonicalize_axes(const Eigen::Matrix3d& R, const Eigen::MatrixXd& X) {
    const Eigen::MatrixXd Y = X * R.transpose();
    const double n = static_cast<double>(X.rows());
    std::array<double, 3> m2{}, m3{};
    for (int k = 0; k < 3; ++k) {
        m2[k] = Y.col(k).array().square().sum() / n;
        m3[k] = Y.col(k).array().cube().sum() / n;
    }
    std::array<int, 3> order = {0, 1, 2};
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return m2[a] > m2[b]; });
    Eigen::Matrix3d Q;
    std::array<double, 3> t3{};
    for (int k = 0; k < 3; ++k) {
        Q.row(k) = R.row(order[k]);
        t3[k] = m3[order[k]];
    }
    std::array<int, 3> by_m3 = {0, 1, 2};
    std::stable_sort(by_m3.begin(), by_m3.end(),
                     [&](int a, int b) { return std::abs(t3[a]) > std::abs(t3[b]); });
    for (int j = 0; j < 2; ++j)
        if (t3[by_m3[j]] < 0) Q.row(by_m3[j]) *= -1.0;
    if (Q.determinant() < 0) Q.row(by_m3[2]) *= -1.0;
    return Q;
}

double aabb_volume(const Eigen::MatrixXd& X, const Eigen::Matrix3d& R) {
    const Eigen::MatrixXd Y = X * R.transpose();
    const Eigen::RowVector3d ext = Y.colwise().maxCoeff() - Y.colwise().minCoeff();
    return ext.prod();
}

// Uniform in [0, 1) from the raw 64-bit output (platform independent, unlike the distributions).
double uniform01(std::mt19937_64& g) {
    return static_cast<double>(g() >> 11) * 0x1.0p-53;
}

Eigen::Matrix3d random_rotation(std::mt19937_64& g) {
    Eigen::Vector4d q;
    double n2;
    do {
        for (int i = 0; i < 4; ++i) q[i] = 2.0 * uniform01(g) - 1.0;
        n2 = q.squaredNorm();
    } while (n2 > 1.0 || n2 < 1e-6);
    q /= std::sqrt(n2);
    return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
}

// The vector helpers below are inlined into the clones: no call passes a vector between code built
// for different targets.
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

typedef double v4d __attribute__((vector_size(32)));
typedef double v8d __attribute__((vector_size(64)));
typedef long long v4l __attribute__((vector_size(32)));
typedef long long v8l __attribute__((vector_size(64)));

template <typename D>
inline D load_doubles(const double* p) {
    D v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

// |v| lane by lane: the sign bit cleared (as fabs; -0 becomes +0).
template <typename D, typename L>
inline D abs_doubles(D v) {
    L b;
    std::memcpy(&b, &v, sizeof b);
    b &= std::numeric_limits<long long>::max();
    std::memcpy(&v, &b, sizeof v);
    return v;
}

// e_i of detail::rectilinearity_sum for the W consecutive i from `at`: D = double and L = long long
// for one, D and L vectors of 4 or 8 lanes for 4 or 8.
template <typename D, typename L>
inline D rect_terms(const double* x, const double* y, const double* z, Eigen::Index at, const double* q) {
    const D X = load_doubles<D>(x + at), Y = load_doubles<D>(y + at), Z = load_doubles<D>(z + at);
    const D r0 = (q[0] * X + q[1] * Y) + q[2] * Z;
    const D r1 = (q[3] * X + q[4] * Y) + q[5] * Z;
    const D r2 = (q[6] * X + q[7] * Y) + q[8] * Z;
    return (abs_doubles<D, L>(r0) + abs_doubles<D, L>(r1)) + abs_doubles<D, L>(r2);
}

}  // namespace

// Eigen's sum() of a dynamic array expression in packets of two (Eigen/src/Core/Redux.h, linear
// vectorised traversal; the expression has no aligned start): packets p0 = (e0, e1) and p1 = (e2, e3)
// take every following pair in turn up to the last multiple of four, p0 += p1, then p0 takes the
// pair before the last multiple of two if there is one; the result is p0's first lane plus its
// second, then the odd last term. Fewer than four terms: e0 + e1 (+ e2); one term: e0. Lane k of
// the four-lane sum below is p0 or p1's lane k mod 2, with the same terms added in the same order.
CANONFORM_CLONES_AVX512 double detail::rectilinearity_sum(const double* x, const double* y, const double* z,
                                                          Eigen::Index n, const Eigen::Matrix3d& Q) {
    const double q[9] = {Q(0, 0), Q(0, 1), Q(0, 2), Q(1, 0), Q(1, 1), Q(1, 2), Q(2, 0), Q(2, 1), Q(2, 2)};
    const auto term = [&](Eigen::Index i) { return rect_terms<double, long long>(x, y, z, i, q); };
    if (n <= 0) return 0.0;
    if (n < 2) return term(0);
    if (n < 4) return n == 3 ? (term(0) + term(1)) + term(2) : term(0) + term(1);
    const Eigen::Index end4 = n / 4 * 4;
    v4d acc = rect_terms<v4d, v4l>(x, y, z, 0, q);
    Eigen::Index i = 4;
    for (; i + 8 <= end4; i += 8) {
        const v8d e = rect_terms<v8d, v8l>(x, y, z, i, q);
        const v4d lo = {e[0], e[1], e[2], e[3]}, hi = {e[4], e[5], e[6], e[7]};
        acc += lo;
        acc += hi;
    }
    for (; i < end4; i += 4) acc += rect_terms<v4d, v4l>(x, y, z, i, q);
    double p0 = acc[0] + acc[2], p1 = acc[1] + acc[3];
    if (n - end4 >= 2) {
        p0 += term(end4);
        p1 += term(end4 + 1);
    }
    double s = p0 + p1;
    if (n % 2) s += term(n - 1);
    return s;
}

namespace {

// Rectilinearity objective on area vectors already in the PCA frame, kept as three coordinate
// arrays (detail::rectilinearity_sum).
struct RectCost {
    Eigen::ArrayXd x, y, z;
    double inv_area;
    RectCost(const Eigen::Matrix3Xd& A, double inv_area_)
        : x(A.row(0).transpose().array()),
          y(A.row(1).transpose().array()),
          z(A.row(2).transpose().array()),
          inv_area(inv_area_) {}
    double operator()(const Eigen::Matrix3d& Q) const {
        return detail::rectilinearity_sum(x.data(), y.data(), z.data(), x.size(), Q) * inv_area;
    }
};

// Area vectors summed per direction bin (cube map: the dominant axis and its sign, then bins x bins
// cells over the other two coordinates divided by the dominant one): the coarse restarts' objective.
Eigen::Matrix3Xd binned_area_vectors(const Eigen::Matrix3Xd& A, int bins) {
    std::vector<Eigen::Vector3d> sum(static_cast<size_t>(6 * bins * bins), Eigen::Vector3d::Zero());
    std::vector<char> used(sum.size(), 0);
    for (Eigen::Index f = 0; f < A.cols(); ++f) {
        const Eigen::Vector3d a = A.col(f);
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (std::abs(a[k]) > std::abs(a[axis])) axis = k;
        const double big = std::abs(a[axis]);
        if (!(big > 0)) continue;
        const auto cell = [&](double t) {
            return std::clamp(static_cast<int>((t / big + 1.0) * 0.5 * bins), 0, bins - 1);
        };
        const int key =
            ((axis * 2 + (a[axis] < 0)) * bins + cell(a[(axis + 1) % 3])) * bins + cell(a[(axis + 2) % 3]);
        sum[static_cast<size_t>(key)] += a;
        used[static_cast<size_t>(key)] = 1;
    }
    Eigen::Matrix3Xd B(3, std::count(used.begin(), used.end(), 1));
    Eigen::Index c = 0;
    for (size_t k = 0; k < sum.size(); ++k)
        if (used[k]) B.col(c++) = sum[k];
    return B;
}

// Nelder-Mead over the rotation vector x of small_rotation(x) Q0; returns the best rotation and its
// cost.
// Standard coefficients (reflection 1, expansion 2, contraction 1/2, shrink 1/2).
std::pair<Eigen::Matrix3d, double> nelder_mead(const RectCost& cost, const Eigen::Matrix3d& Q0, double step,
                                               int max_evals, double ftol, double xtol) {
    auto f = [&](const Eigen::Vector3d& x) { return cost(small_rotation(x) * Q0); };
    std::array<Eigen::Vector3d, 4> s;
    std::array<double, 4> fv{};
    s[0].setZero();
    for (int i = 1; i < 4; ++i) {
        s[i].setZero();
        s[i][i - 1] = step;
    }
    for (int i = 0; i < 4; ++i) fv[i] = f(s[i]);
    int evals = 4;
    std::array<int, 4> idx = {0, 1, 2, 3};
    while (evals < max_evals) {
        std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return fv[a] < fv[b]; });
        const int lo = idx[0], hi = idx[3], nh = idx[2];
        double diam = 0.0;
        for (int i = 1; i < 4; ++i) diam = std::max(diam, (s[idx[i]] - s[lo]).cwiseAbs().maxCoeff());
        if (fv[hi] - fv[lo] <= ftol && diam <= xtol) break;
        if (diam <= 1e-13) break;
        const Eigen::Vector3d cen = (s[idx[0]] + s[idx[1]] + s[idx[2]]) / 3.0;
        const Eigen::Vector3d xr = cen + (cen - s[hi]);
        const double fr = f(xr);
        ++evals;
        if (fr < fv[lo]) {
            const Eigen::Vector3d xe = cen + 2.0 * (cen - s[hi]);
            const double fe = f(xe);
            ++evals;
            if (fe < fr)
                s[hi] = xe, fv[hi] = fe;
            else
                s[hi] = xr, fv[hi] = fr;
        } else if (fr < fv[nh]) {
            s[hi] = xr, fv[hi] = fr;
        } else {
            const bool outside = fr < fv[hi];
            const Eigen::Vector3d xc = outside ? Eigen::Vector3d(cen + 0.5 * (xr - cen))
                                               : Eigen::Vector3d(cen + 0.5 * (s[hi] - cen));
            const double fc = f(xc);
            ++evals;
            if (fc < (outside ? fr : fv[hi])) {
                s[hi] = xc, fv[hi] = fc;
            } else {
                for (int i = 1; i < 4; ++i) {
                    const int k = idx[i];
                    s[k] = s[lo] + 0.5 * (s[k] - s[lo]);
                    fv[k] = f(s[k]);
                    ++evals;
                }
            }
        }
    }
    int best = 0;
    for (int i = 1; i < 4; ++i)
        if (fv[i] < fv[best]) best = i;
    return {small_rotation(s[best]) * Q0, fv[best]};
}

// How a start is minimised: Nelder-Mead rounds from the best point so far, the r-th with initial
// step 0.3 * 0.2^r; each round stops when its simplex is within xtol (rotation vector) and ftol
// (cost) or after 600 evaluations.
struct Schedule {
    int rounds;
    double xtol, ftol;
    bool every_round;  ///< run all rounds (else stop after the first round that does not improve)
};
// Coarse restarts: only the basin matters (the refinement starts over with large steps).
constexpr Schedule kCoarse{3, 1e-4, 1e-8, false};
// Refinement: a fixed number of rounds. A stopping rule "stop when a round does not improve" was
// decided by rounding noise (an improvement of 1e-16 or none), and an extra round often found a
// lower minimum 1e-3 rad away, so the result moved with the last bit of the input. Three rounds to
// 1e-8 rad: a rotation that far off moves a vertex of the unit-radius mesh by 1e-8, a millionth of
// a view's pixel; five rounds to 1e-11 (the schedule before) took twice the cost evaluations, the
// descriptor's largest single cost after SIFT, and reached the same rotations within that
// (docs/benchmarks.md, "View descriptor": the figures and the retrieval check).
constexpr Schedule kRefine{3, 1e-8, 1e-11, true};

std::pair<Eigen::Matrix3d, double> minimise_from(const RectCost& cost, const Eigen::Matrix3d& Q0,
                                                 const Schedule& sc) {
    Eigen::Matrix3d Q = Q0;
    double fq = cost(Q);
    double step = 0.3;
    for (int r = 0; r < sc.rounds; ++r) {
        auto [Qn, fn] = nelder_mead(cost, Q, step, 600, sc.ftol, sc.xtol);
        const bool improved = fn < fq * (1.0 - 1e-12);  // well above rounding noise (~1e-15)
        if (fn <= fq) {
            // Re-orthonormalise (the product of many rotations drifts by rounding).
            Eigen::JacobiSVD<Eigen::Matrix3d> svd(Qn, Eigen::ComputeFullU | Eigen::ComputeFullV);
            Q = svd.matrixU() * svd.matrixV().transpose();
            fq = cost(Q);
        }
        if (!improved && r > 0 && !sc.every_round) break;
        step *= 0.2;
    }
    return {Q, fq};
}

}  // namespace

double projected_area_ratio(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Matrix3d& R) {
    validate(V, F);
    const Eigen::Matrix3Xd A = area_vectors(V, F);
    const double total = A.colwise().norm().sum();
    if (!(total > 0)) throw InputError("the mesh has zero surface area");
    return RectCost{A, 1.0 / total}(R);
}

PoseNormalization normalize_pose(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const PoseOptions& options) {
    validate(V, F);
    if (options.restarts < 1) throw InputError("pose normalisation needs at least one rectilinearity start");
    if (options.direction_bins < 0 || options.direction_bins > 1024)
        throw InputError("pose normalisation: direction_bins must be in [0, 1024] (0 = no binning)");
    PoseNormalization out;
    out.centre = V.colwise().mean();
    Eigen::MatrixXd X = V.rowwise() - out.centre;
    const double rmax = X.rowwise().stableNorm().maxCoeff();  // no over- or underflow for 1e200 or 1e-200
    if (!(rmax > 0) || !std::isfinite(rmax)) throw InputError("all vertices of the mesh are at one point");
    out.scale = 1.0 / rmax;
    X *= out.scale;

    const Eigen::Matrix3Xd A = area_vectors(X, F);
    const double total = A.colwise().norm().sum();
    if (!(total > 0)) throw InputError("the mesh has zero surface area");

    // PCA candidate.
    const Eigen::Matrix3d cov = covariance(X);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    if (eig.info() != Eigen::Success)
        throw NumericalError("pose normalisation: the PCA eigen-decomposition failed");
    Eigen::Matrix3d Rpca;
    for (int k = 0; k < 3; ++k) Rpca.row(k) = eig.eigenvectors().col(2 - k).transpose();
    Rpca = canonicalize_axes(Rpca, X);

    // Rectilinearity candidate, optimised in the PCA frame.
    const Eigen::Matrix3Xd Apca = Rpca * A;
    const RectCost cost{Apca, 1.0 / total};
    // The coarse restarts on the area vectors summed per direction bin (if that shrinks them).
    Eigen::Matrix3Xd Abinned;
    if (options.direction_bins > 0) Abinned = binned_area_vectors(Apca, options.direction_bins);
    const bool binned = options.direction_bins > 0 && Abinned.cols() < Apca.cols();
    const RectCost coarse{binned ? Abinned : Apca, 1.0 / total};
    std::mt19937_64 gen(options.seed);
    Eigen::Matrix3d best_Q = Eigen::Matrix3d::Identity();
    double best_f = 1e300;
    for (int k = 0; k < options.restarts; ++k) {
        const Eigen::Matrix3d Q0 = k == 0 ? Eigen::Matrix3d::Identity() : random_rotation(gen);
        auto [Q, fq] = minimise_from(coarse, Q0, kCoarse);
        if (fq < best_f) best_f = fq, best_Q = Q;
    }
    // Restarts often reach one minimum, or minima related by one of the 24 rotations of the cube
    // (P is invariant under them), with costs equal up to rounding; which one wins is then decided
    // by rounding. The winner's axes are therefore canonicalised (step 4) before it is refined, so
    // that the refinement starts from the same frame whichever one won.
    best_Q = canonicalize_axes(best_Q * Rpca, X) * Rpca.transpose();
    best_Q = minimise_from(cost, best_Q, kRefine).first;
    Eigen::Matrix3d Rrect = canonicalize_axes(best_Q * Rpca, X);

    out.pca_projected_area = RectCost{A, 1.0 / total}(Rpca);
    out.rect_projected_area = RectCost{A, 1.0 / total}(Rrect);
    out.pca_cost = aabb_volume(X, Rpca);
    out.rect_cost = aabb_volume(X, Rrect);
    out.used_rectilinearity = out.rect_cost < out.pca_cost;
    out.R = out.used_rectilinearity ? Rrect : Rpca;
    return out;
}

Eigen::MatrixXd apply_pose(const PoseNormalization& pose, const Eigen::MatrixXd& V) {
    if (V.cols() != 3) throw InputError("apply_pose needs a #V x 3 vertex matrix");
    return ((V.rowwise() - pose.centre) * pose.scale) * pose.R.transpose();
}

}  // namespace canonform::views
