// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/mesh_topology.h"

#include "canonform/common/errors.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <sstream>
#include <utility>

namespace canonform::surface {

namespace {

/// Directed half-edges (min, max, face) of F, sorted: the basis of the edge queries below.
/// A counting sort by the smaller vertex, then a stable sort by the larger one within each (small)
/// bucket: the order std::sort gave on (key, face), in linear time (it sorted 6M half-edges at 1M
/// vertices, three times per canonical form).
std::vector<std::pair<long long, int>> sorted_edge_keys(const Eigen::MatrixXi& F, long long n) {
    const size_t m = static_cast<size_t>(F.rows()) * 3;
    std::vector<size_t> start(static_cast<size_t>(n) + 1, 0);
    for (int f = 0; f < F.rows(); ++f)
        for (int c = 0; c < 3; ++c) ++start[static_cast<size_t>(std::min(F(f, c), F(f, (c + 1) % 3))) + 1];
    for (size_t v = 0; v < static_cast<size_t>(n); ++v) start[v + 1] += start[v];
    std::vector<std::pair<long long, int>> keys(m);
    for (int f = 0; f < F.rows(); ++f) {
        for (int c = 0; c < 3; ++c) {
            long long a = F(f, c), b = F(f, (c + 1) % 3);
            if (a > b) std::swap(a, b);
            keys[start[static_cast<size_t>(a)]++] = {a * n + b, f};
        }
    }
    // start[v] is now the end of bucket v (the beginning of bucket v + 1).
    size_t begin = 0;
    for (size_t v = 0; v < static_cast<size_t>(n); ++v) {
        const size_t end = start[v];
        // Faces are already ascending within the bucket: a stable sort by key keeps them so.
        // Buckets hold a vertex's half-edges to larger neighbours (about 3): an insertion sort,
        // stable and without std::stable_sort's buffer allocation per bucket; large fans fall
        // back to it.
        const auto by_key = [](const auto& x, const auto& y) { return x.first < y.first; };
        if (end - begin > 32) {
            std::stable_sort(keys.begin() + static_cast<std::ptrdiff_t>(begin),
                             keys.begin() + static_cast<std::ptrdiff_t>(end), by_key);
        } else {
            for (size_t k = begin + 1; k < end; ++k) {
                const auto key = keys[k];
                size_t j = k;
                for (; j > begin && by_key(key, keys[j - 1]); --j) keys[j] = keys[j - 1];
                keys[j] = key;
            }
        }
        begin = end;
    }
    return keys;
}

/// The unique edges (a < b, ascending) of sorted half-edge keys a * n + b.
Eigen::MatrixXi edges_of_keys(const std::vector<std::pair<long long, int>>& keys, long long n) {
    std::vector<long long> uniq;
    uniq.reserve(keys.size() / 2 + 1);
    for (size_t k = 0; k < keys.size(); ++k)
        if (k == 0 || keys[k].first != keys[k - 1].first) uniq.push_back(keys[k].first);
    Eigen::MatrixXi E(static_cast<Eigen::Index>(uniq.size()), 2);
    for (size_t e = 0; e < uniq.size(); ++e) {
        E(static_cast<Eigen::Index>(e), 0) = static_cast<int>(uniq[e] / n);
        E(static_cast<Eigen::Index>(e), 1) = static_cast<int>(uniq[e] % n);
    }
    return E;
}

/// Vertices on an edge of one face, from sorted half-edge keys a * n + b.
std::vector<bool> boundary_of_keys(const std::vector<std::pair<long long, int>>& keys, int n) {
    std::vector<bool> on_boundary(static_cast<size_t>(n), false);
    for (size_t k = 0; k < keys.size();) {
        size_t m = k;
        while (m < keys.size() && keys[m].first == keys[k].first) ++m;
        if (m - k == 1) {
            on_boundary[static_cast<size_t>(keys[k].first / n)] = true;
            on_boundary[static_cast<size_t>(keys[k].first % n)] = true;
        }
        k = m;
    }
    return on_boundary;
}

}  // namespace

Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F) {
    const long long n = F.size() ? static_cast<long long>(F.maxCoeff()) + 1 : 0;
    return edges_of_keys(sorted_edge_keys(F, n), n);
}

std::vector<bool> boundary_vertices(int n, const Eigen::MatrixXi& F) {
    return boundary_of_keys(sorted_edge_keys(F, n), n);
}

namespace {

/// The checks of validate_mesh() in order. Each problem goes to `found`, which throws for
/// validate_mesh() (so it stops at the first) and collects for mesh_problems(). A check runs only
/// when the ones it relies on passed: nothing reads outside V, and no geometry is judged on
/// non-finite coordinates.
MeshReport run_checks(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const ValidationOptions& options,
                      const std::function<void(const char* kind, const std::string& message)>& found) {
    MeshReport r;
    r.vertices = static_cast<int>(V.rows());
    r.faces = static_cast<int>(F.rows());
    auto problem = [&](const char* kind, const std::ostringstream& msg) { found(kind, msg.str()); };
    if (V.rows() == 0) {
        found("empty", "the mesh is empty: it has no vertices");
        return r;
    }
    if (V.cols() != 3 || (F.rows() > 0 && F.cols() != 3)) {
        found("shape", "the mesh must have 3D vertices and triangular faces");
        return r;
    }
    if (F.rows() == 0) {
        std::ostringstream msg;
        msg << "the mesh has " << V.rows()
            << " vertices and no faces (a point cloud): a triangle mesh is needed";
        problem("point_cloud", msg);
        return r;
    }
    Eigen::Index non_finite = 0, first_non_finite = -1;
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
        if (!V.row(v).allFinite()) {
            if (first_non_finite < 0) first_non_finite = v;
            ++non_finite;
        }
    }
    if (non_finite > 0) {
        std::ostringstream msg;
        msg << "the mesh has " << non_finite << " vertices with NaN or infinite coordinates (first: vertex "
            << first_non_finite << ")";
        problem("non_finite", msg);
    }
    // Indices before anything uses F: a negative one or one >= #V would read outside V.
    Eigen::Index out_of_range = 0, first_bad = -1;
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        bool bad = false;
        for (int c = 0; c < 3; ++c) bad = bad || F(f, c) < 0 || F(f, c) >= V.rows();
        if (bad) {
            if (first_bad < 0) first_bad = f;
            ++out_of_range;
        }
    }
    if (first_bad >= 0) {
        std::ostringstream msg;
        msg << "face indices out of range: face " << first_bad << " is (" << F(first_bad, 0) << ", "
            << F(first_bad, 1) << ", " << F(first_bad, 2) << "), but they must lie in [0, " << V.rows() - 1
            << "]";
        if (out_of_range > 1) msg << " (" << out_of_range << " faces in all)";
        problem("index_out_of_range", msg);
        return r;  // nothing below may read F
    }
    if (V.rows() < options.min_vertices) {
        std::ostringstream msg;
        msg << "the mesh has only " << V.rows() << " vertices; at least " << options.min_vertices
            << " are needed";
        problem("too_few_vertices", msg);
    }
    // Geometry, on finite coordinates only.
    double diag = 0;
    if (non_finite == 0) {
        // Size: the computations square and sum coordinates in double precision.
        const double largest = V.cwiseAbs().maxCoeff();
        if (largest > options.max_coordinate) {
            std::ostringstream msg;
            msg << "the mesh's coordinates reach " << largest << ", beyond the " << options.max_coordinate
                << " that the computation handles in double precision: rescale the mesh (e.g. MeshLab's "
                   "'Transform: Scale, Normalize')";
            problem("too_large", msg);
        }
        // Degenerate faces: a repeated vertex, or an area that is zero at the scale of the mesh
        // (measured in units of the bounding-box diagonal, so that neither tiny nor huge coordinates
        // over- or underflow).
        diag = (V.colwise().maxCoeff() - V.colwise().minCoeff()).stableNorm();
        if (!(diag > 0)) {
            std::ostringstream msg;
            msg << "all " << V.rows() << " vertices of the mesh are at one point";
            problem("one_point", msg);
        }
    }
    int degenerate = 0, first_degenerate = -1;
    for (int f = 0; f < F.rows(); ++f) {
        const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
        bool bad = (a == b || b == c || a == c);
        if (!bad && diag > 0 && std::isfinite(diag)) {
            const Eigen::Vector3d e1 = (V.row(b) - V.row(a)) / diag, e2 = (V.row(c) - V.row(a)) / diag;
            bad = !(0.5 * e1.cross(e2).norm() > options.degenerate_area);
        }
        if (bad) {
            if (first_degenerate < 0) first_degenerate = f;
            ++degenerate;
        }
    }
    if (degenerate > 0) {
        std::ostringstream msg;
        msg << "the mesh has " << degenerate
            << " degenerate faces (zero area or a repeated vertex; first: face " << first_degenerate
            << "); remove them first, e.g. with --repair (the tool, retrieve) or the filters' 'Repair' "
               "parameter, or MeshLab's 'Remove Zero Area Faces' and 'Remove Duplicate Vertices'";
        problem("degenerate_faces", msg);
    }
    // Edges: count incident faces per undirected edge.
    const long long n = V.rows();
    auto keys = sorted_edge_keys(F, n);
    int nonmanifold = 0;
    long long first_nm = -1;
    for (size_t k = 0; k < keys.size();) {
        size_t m = k;
        while (m < keys.size() && keys[m].first == keys[k].first) ++m;
        ++r.edges;
        if (m - k == 1) ++r.boundary_edges;
        if (m - k > 2) {
            if (first_nm < 0) first_nm = keys[k].first;
            ++nonmanifold;
        }
        k = m;
    }
    if (nonmanifold > 0) {
        std::ostringstream msg;
        msg << "the mesh has " << nonmanifold << " non-manifold edges (shared by more than two faces; "
            << "first: vertices " << first_nm / n << "-" << first_nm % n
            << "); repair it, e.g. with MeshLab's 'Repair non Manifold Edges'";
        problem("non_manifold_edges", msg);
    }
    std::vector<bool> referenced(static_cast<size_t>(n), false);
    for (int f = 0; f < F.rows(); ++f)
        for (int c = 0; c < 3; ++c) referenced[static_cast<size_t>(F(f, c))] = true;
    const auto unref = std::count(referenced.begin(), referenced.end(), false);
    if (unref > 0) {
        std::ostringstream msg;
        msg << "the mesh has " << unref
            << " vertices that belong to no face; remove them first, e.g. with MeshLab's 'Remove "
               "Unreferenced Vertices'";
        problem("unreferenced_vertices", msg);
    }
    r.edge_list = edges_of_keys(keys, n);  // = unique_edges(F): the same sorted keys
    numerics::connected_components(static_cast<int>(n), r.edge_list, &r.components);
    if (options.require_single_component && r.components > 1) {
        std::ostringstream msg;
        msg << "the mesh has " << r.components
            << " connected components; the method needs one. Keep the largest, e.g. with "
               "MeshLab's 'Remove Isolated pieces (wrt Diameter)'";
        problem("components", msg);
    }
    r.boundary = boundary_of_keys(keys, static_cast<int>(n));  // = boundary_vertices(n, F)
    r.boundary_loops_vertices = static_cast<int>(std::count(r.boundary.begin(), r.boundary.end(), true));
    r.euler_characteristic = r.vertices - r.edges + r.faces;
    return r;
}

}  // namespace

MeshReport validate_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                         const ValidationOptions& options) {
    return run_checks(V, F, options,
                      [](const char*, const std::string& message) { throw InputError(message); });
}

std::vector<MeshProblem> mesh_problems(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const ValidationOptions& options, MeshReport* report) {
    std::vector<MeshProblem> found;
    MeshReport r = run_checks(V, F, options, [&](const char* kind, const std::string& message) {
        found.push_back({kind, message});
    });
    if (report) *report = std::move(r);
    return found;
}

double mean_relative_edge_change(const Eigen::MatrixXd& V0, const Eigen::MatrixXd& V1,
                                 const Eigen::MatrixXi& E) {
    double change = 0;
    for (Eigen::Index e = 0; e < E.rows(); ++e) {
        const double d0 = (V0.row(E(e, 0)) - V0.row(E(e, 1))).norm();
        const double d1 = (V1.row(E(e, 0)) - V1.row(E(e, 1))).norm();
        change += std::abs(d1 - d0) / d0;
    }
    return E.rows() ? change / static_cast<double>(E.rows()) : 0.0;
}

}  // namespace canonform::surface
