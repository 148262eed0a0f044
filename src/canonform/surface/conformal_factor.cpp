// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/conformal_factor.h"

#include "canonform/surface/cotan_laplacian.h"
#include "canonform/surface/gaussian_curvature.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/surface/vertex_areas.h"

#include "canonform/numerics/sparse_cholesky.h"

#include <cmath>
#include <sstream>

namespace canonform::surface {

Eigen::MatrixXd normalize_scale(const Eigen::MatrixXd& V, Eigen::RowVector3d* centroid, double* scale) {
    const Eigen::RowVector3d c = V.colwise().mean();
    Eigen::MatrixXd X = V.rowwise() - c;
    // Largest radius without over- or underflow for 1e200 or 1e-200: the rows scaled by the
    // largest |coordinate| first (one division per entry; stableNorm() per row costs far more).
    const double m = X.cwiseAbs().maxCoeff();
    const double r = m > 0 ? m * std::sqrt((X / m).rowwise().squaredNorm().maxCoeff()) : m;
    if (!(r > 0)) throw InputError("all vertices of the mesh coincide");
    X /= r;
    if (centroid) *centroid = c;
    if (scale) *scale = r;
    return X;
}

namespace {
/// L without its row and column 0 (the pinned system), copied column by column: what
/// L.bottomRightCorner(n - 1, n - 1) gives, without Eigen's general block assignment.
Eigen::SparseMatrix<double> without_first_row_and_column(const Eigen::SparseMatrix<double>& L) {
    const Eigen::Index n = L.rows();
    const int* outer = L.outerIndexPtr();
    const int* inner = L.innerIndexPtr();
    const double* values = L.valuePtr();
    Eigen::SparseMatrix<double> R(n - 1, n - 1);
    Eigen::Index kept = 0;
    for (Eigen::Index c = 1; c < n; ++c)
        for (int p = outer[c]; p < outer[c + 1]; ++p) kept += inner[p] > 0;
    R.resizeNonZeros(kept);
    int* r_outer = R.outerIndexPtr();
    int* r_inner = R.innerIndexPtr();
    double* r_values = R.valuePtr();
    int q = 0;
    r_outer[0] = 0;
    for (Eigen::Index c = 1; c < n; ++c) {
        for (int p = outer[c]; p < outer[c + 1]; ++p)
            if (inner[p] > 0) {
                r_inner[q] = inner[p] - 1;
                r_values[q++] = values[p];
            }
        r_outer[c] = q;
    }
    return R;
}
}  // namespace

Parameter normalize_parameter() {
    return Parameter::flag("normalize")
        .default_value("true")
        .label("Normalise to [0, 1]")
        .help("store (phi - min) / (max - min) instead of the raw conformal factor (mean zero)")
        .alias("raw");
}

ConformalFactorResult conformal_factor(const Eigen::MatrixXd& V0, const Eigen::MatrixXi& F,
                                       const ConformalFactorOptions& options) {
    MeshReport report;  // the boundary comes with the validation, or from the caller's
    if (options.validate) report = validate_mesh(V0, F);
    const std::vector<bool>& boundary = options.validate ? report.boundary : options.boundary;
    report_progress(options.progress, 0.0, "conformal factor: curvature");
    Eigen::MatrixXd V = normalize_scale(V0);
    const Eigen::Index n = V.rows();

    ConformalFactorResult r;
    r.curvature = gaussian_curvature(V, F, boundary, options.threads);
    const Eigen::VectorXd A = vertex_areas(V, F);
    r.target = r.curvature.sum() * A / A.sum();
    const Eigen::VectorXd rhs = r.curvature - r.target;  // (D - W) phi = K0 - KT, see header

    report_progress(options.progress, 0.2, "conformal factor: factorising");
    // Pin vertex 0: drop its row and column. Only Lr and L's column 0 (for the residual) are
    // kept, not L itself, and the scaled copy of V goes too: memory at 1M vertices.
    Eigen::SparseMatrix<double> Lr;
    Eigen::SparseVector<double> L0;
    {
        const Eigen::SparseMatrix<double> L = cotan_laplacian(V, F, options.threads);
        Lr = without_first_row_and_column(L);
        L0 = L.col(0);
    }
    V.resize(0, 3);
    Eigen::VectorXd phi(n);
    phi(0) = 0;
    if (numerics::use_multigrid(options.linear_solver, n - 1)) {
        numerics::AmgOptions amg_options;
        amg_options.threads = options.threads;
        const numerics::AmgPreconditioner amg(Lr, amg_options);
        report_progress(options.progress, 0.7, "conformal factor: solving (multigrid)");
        Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n - 1, 1);
        const numerics::PcgReport rep = amg.pcg(Eigen::MatrixXd(rhs.tail(n - 1)), x, 1e-10, 500);
        if (!rep.converged)
            throw NumericalError(
                "conformal factor: the multigrid solve did not converge (is the mesh "
                "free of degenerate triangles?)");
        phi.tail(n - 1) = x.col(0);
    } else {
        numerics::SparseCholesky solver;
        if (!solver.compute(Lr))
            throw NumericalError(
                "conformal factor: the Cholesky factorisation of the cotangent Laplacian "
                "failed (is the mesh connected and free of degenerate triangles?)");
        report_progress(options.progress, 0.7, "conformal factor: solving");
        phi.tail(n - 1) = solver.solve(Eigen::MatrixXd(rhs.tail(n - 1)));
        if (!solver.ok()) throw NumericalError("conformal factor: the linear solve failed");
        r.ordering = solver.ordering();
    }
    if (!phi.allFinite())
        throw NumericalError("conformal factor: the linear solve produced non-finite values");

    const double scale = rhs.lpNorm<Eigen::Infinity>();
    // L phi from its pinned part and its column 0 (L is symmetric, phi(0) = 0).
    Eigen::VectorXd Lphi(n);
    Lphi(0) = L0.dot(phi);
    Lphi.tail(n - 1) = Lr * phi.tail(n - 1);
    r.residual = scale > 0 ? (Lphi - rhs).lpNorm<Eigen::Infinity>() / scale : 0.0;
    if (!(r.residual <= options.residual_tolerance)) {
        std::ostringstream m;
        m << "conformal factor: relative residual " << r.residual << " above tolerance "
          << options.residual_tolerance << " (ill-conditioned mesh: obtuse or sliver triangles?)";
        throw NumericalError(m.str());
    }
    phi.array() -= A.dot(phi) / A.sum();
    r.raw = phi;
    const double lo = phi.minCoeff(), hi = phi.maxCoeff();
    r.normalized =
        hi > lo ? Eigen::VectorXd((phi.array() - lo) / (hi - lo)) : Eigen::VectorXd::Constant(n, 0.5);
    report_progress(options.progress, 1.0, "conformal factor: done");
    return r;
}

}  // namespace canonform::surface
