// SPDX-License-Identifier: GPL-3.0-or-later
// Test helper: prints facts about a mesh file as JSON for the end-to-end tests:
//   canonform_plycheck FILE [REFERENCE]
// vertices, faces, quality range, and with REFERENCE: the largest quality and position
// differences, vertex by vertex, and the RMS position difference after the best rigid alignment.
#include "canonform/io/mesh_io.h"
#include "canonform/numerics/rigid_alignment.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3) {
        std::fprintf(stderr, "usage: canonform_plycheck FILE [REFERENCE]\n");
        return 2;
    }
    try {
        const auto m = canonform::io::read_mesh(argv[1]);
        const Eigen::VectorXd q = canonform::io::read_ply_quality(argv[1]);
        nlohmann::ordered_json j = {
            {"vertices", m.V.rows()}, {"faces", m.F.rows()}, {"has_quality", q.size() ? 1 : 0}};
        if (q.size()) {
            j["quality_min"] = q.minCoeff();
            j["quality_max"] = q.maxCoeff();
        }
        if (argc == 3) {
            const auto r = canonform::io::read_mesh(argv[2]);
            const Eigen::VectorXd rq = canonform::io::read_ply_quality(argv[2]);
            const bool same = r.V.rows() == m.V.rows();
            j["same_vertex_count"] = same ? 1 : 0;
            if (same) {
                j["max_position_diff"] = (r.V - m.V).cwiseAbs().maxCoeff();
                j["aligned_rms"] = canonform::numerics::align_rigid(m.V, r.V).rms;
                if (q.size() && rq.size() == q.size()) j["max_quality_diff"] = (rq - q).cwiseAbs().maxCoeff();
            }
        }
        std::printf("%s\n", j.dump().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "canonform_plycheck: %s\n", e.what());
        return 1;
    }
    return 0;
}
