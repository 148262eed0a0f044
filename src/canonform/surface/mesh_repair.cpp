// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/mesh_repair.h"

#include "canonform/common/errors.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <set>
#include <sstream>
#include <unordered_map>

namespace canonform::surface {

namespace {

/// Union-find over vertices (components of the faces' vertex sets).
struct Components {
    explicit Components(int n) : parent(static_cast<size_t>(n)) {
        std::iota(parent.begin(), parent.end(), 0);
    }
    int find(int v) {
        while (parent[static_cast<size_t>(v)] != v) {
            parent[static_cast<size_t>(v)] = parent[static_cast<size_t>(parent[static_cast<size_t>(v)])];
            v = parent[static_cast<size_t>(v)];
        }
        return v;
    }
    void join(int a, int b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
    }
    std::vector<int> parent;
};

struct PointKey {
    std::uint64_t bits[3];
    bool operator==(const PointKey& o) const {
        return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
    }
};
struct PointHash {
    size_t operator()(const PointKey& k) const {
        std::uint64_t h = 1469598103934665603ULL;
        for (auto b : k.bits) h = (h ^ b) * 1099511628211ULL;
        return static_cast<size_t>(h ^ (h >> 31));
    }
};

const char* plural(int n, const char* one, const char* many) {
    return n == 1 ? one : many;
}

}  // namespace

bool MeshRepair::changed() const {
    return merged_vertices || degenerate_faces || duplicate_faces || removed_components ||
           unreferenced_vertices;
}

std::string MeshRepair::summary() const {
    std::ostringstream s;
    const auto in_v = vertex_source.size() + static_cast<size_t>(merged_vertices + unreferenced_vertices);
    const auto in_f =
        face_source.size() + static_cast<size_t>(degenerate_faces + duplicate_faces + component_faces);
    if (!changed()) {
        s << "repair: nothing to repair (" << mesh.V.rows() << " vertices, " << mesh.F.rows() << " faces)";
        return s.str();
    }
    std::vector<std::string> parts;
    auto add = [&](int n, const std::string& text) {
        if (n) parts.push_back(std::to_string(n) + " " + text);
    };
    add(merged_vertices,
        std::string(plural(merged_vertices, "duplicate vertex", "duplicate vertices")) + " merged");
    add(degenerate_faces, std::string(plural(degenerate_faces, "zero-area or repeated-vertex face",
                                             "zero-area or repeated-vertex faces")) +
                              " removed");
    add(duplicate_faces,
        std::string(plural(duplicate_faces, "duplicate face", "duplicate faces")) + " removed");
    if (removed_components)
        parts.push_back(std::to_string(removed_components) + " smaller " +
                        plural(removed_components, "component", "components") + " (" +
                        std::to_string(component_faces) + " faces) removed");
    add(unreferenced_vertices,
        std::string(plural(unreferenced_vertices, "unreferenced vertex", "unreferenced vertices")) +
            " dropped");
    s << "repair: ";
    for (size_t k = 0; k < parts.size(); ++k) s << (k ? ", " : "") << parts[k];
    s << ": " << in_v << " -> " << mesh.V.rows() << " vertices, " << in_f << " -> " << mesh.F.rows()
      << " faces";
    return s.str();
}

Parameter repair_parameter() {
    return Parameter::flag("repair")
        .label("Repair the mesh first")
        .help(
            "repair the mesh first: merge duplicate vertices, remove zero-area and duplicate faces, keep the "
            "largest "
            "component, drop unreferenced vertices, and say what changed; off (default): refuse such a mesh, "
            "naming "
            "the problem");
}

MeshRepair repair_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const MeshRepairOptions& options) {
    if (V.cols() != 3 || (F.size() && F.cols() != 3))
        throw InputError("repair needs #V x 3 vertices and #F x 3 faces");
    const int n = static_cast<int>(V.rows());
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        for (int c = 0; c < 3; ++c)
            if (F(f, c) < 0 || F(f, c) >= n)
                throw InputError("face indices out of range: face " + std::to_string(f) + " names vertex " +
                                 std::to_string(F(f, c)) + " of " + std::to_string(n));
    MeshRepair r;

    // 1. Duplicate vertices -> the first with the same coordinates.
    std::vector<int> rep(static_cast<size_t>(n));
    {
        std::unordered_map<PointKey, int, PointHash> first;
        first.reserve(static_cast<size_t>(n));
        for (int v = 0; v < n; ++v) {
            PointKey k;
            for (int c = 0; c < 3; ++c) {
                const double x = V(v, c) == 0 ? 0.0 : V(v, c);  // -0 and +0 are one point
                std::memcpy(&k.bits[c], &x, sizeof x);
            }
            const auto [it, inserted] = first.emplace(k, v);
            rep[static_cast<size_t>(v)] = it->second;
            if (!inserted) ++r.merged_vertices;
        }
    }

    // 2. Degenerate faces, measured in units of the bounding-box diagonal (as validate_mesh()).
    const double diag = n ? (V.colwise().maxCoeff() - V.colwise().minCoeff()).stableNorm() : 0.0;
    std::vector<std::array<int, 3>> faces;
    std::vector<int> source;
    for (int f = 0; f < F.rows(); ++f) {
        const std::array<int, 3> t = {rep[static_cast<size_t>(F(f, 0))], rep[static_cast<size_t>(F(f, 1))],
                                      rep[static_cast<size_t>(F(f, 2))]};
        bool bad = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        if (!bad && diag > 0 && std::isfinite(diag)) {
            const Eigen::Vector3d e1 = (V.row(t[1]) - V.row(t[0])) / diag,
                                  e2 = (V.row(t[2]) - V.row(t[0])) / diag;
            const double area = 0.5 * e1.cross(e2).norm();
            bad =
                std::isfinite(area) && !(area > options.degenerate_area);  // NaN stays for validation to name
        } else if (!bad && diag == 0) {
            bad = true;  // every vertex at one point
        }
        if (bad) {
            ++r.degenerate_faces;
            continue;
        }
        faces.push_back(t);
        source.push_back(f);
    }

    // Keeps the faces (and their source indices) for which keep(face) holds; counts the others.
    const auto keep_faces = [&faces, &source](int* removed, const auto& keep) {
        std::vector<std::array<int, 3>> kept;
        std::vector<int> kept_source;
        for (size_t k = 0; k < faces.size(); ++k) {
            if (!keep(faces[k])) {
                ++*removed;
                continue;
            }
            kept.push_back(faces[k]);
            kept_source.push_back(source[k]);
        }
        faces.swap(kept);
        source.swap(kept_source);
    };

    // 3. Duplicate faces (the same vertex set) -> the first.
    std::set<std::array<int, 3>> seen;
    keep_faces(&r.duplicate_faces, [&seen](std::array<int, 3> key) {
        std::sort(key.begin(), key.end());
        return seen.insert(key).second;
    });

    // 4. The largest component (by faces).
    if (options.keep_largest_component && !faces.empty()) {
        Components cc(n);
        for (const auto& t : faces) {
            cc.join(t[0], t[1]);
            cc.join(t[1], t[2]);
        }
        std::unordered_map<int, int> count;  // root -> faces
        std::vector<int> order;              // roots in order of their first face
        for (const auto& t : faces) {
            const int root = cc.find(t[0]);
            if (count[root]++ == 0) order.push_back(root);
        }
        int best = order.front();
        for (int root : order)
            if (count[root] > count[best]) best = root;
        r.removed_components = static_cast<int>(order.size()) - 1;
        keep_faces(&r.component_faces,
                   [&cc, best](const std::array<int, 3>& t) { return cc.find(t[0]) == best; });
    }

    // 5. Unreferenced vertices (merged ones included) dropped; order kept.
    std::vector<int> index(static_cast<size_t>(n), -1);
    for (const auto& t : faces)
        for (int v : t) index[static_cast<size_t>(v)] = 0;
    int referenced_representatives = 0;
    for (int v = 0; v < n; ++v)
        if (index[static_cast<size_t>(v)] == 0) {
            index[static_cast<size_t>(v)] = static_cast<int>(r.vertex_source.size());
            r.vertex_source.push_back(v);
            ++referenced_representatives;
        }
    r.unreferenced_vertices = n - r.merged_vertices - referenced_representatives;
    r.mesh.V.resize(static_cast<Eigen::Index>(r.vertex_source.size()), 3);
    for (size_t k = 0; k < r.vertex_source.size(); ++k)
        r.mesh.V.row(static_cast<Eigen::Index>(k)) = V.row(r.vertex_source[k]);
    r.mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (size_t k = 0; k < faces.size(); ++k)
        for (int c = 0; c < 3; ++c)
            r.mesh.F(static_cast<Eigen::Index>(k), c) =
                index[static_cast<size_t>(faces[k][static_cast<size_t>(c)])];
    r.face_source = std::move(source);
    return r;
}

}  // namespace canonform::surface
