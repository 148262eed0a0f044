// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target of mesh validation, repair and the canonical-form methods on tiny meshes.
//
// The bytes edit a small closed mesh (an icosahedron, 12 vertices, or its subdivision, 42): byte
// 0 picks the base mesh, the method and whether to repair; then each 8-byte record is one edit -
// move a vertex to a value chosen from a set of hostile ones (0, +-1e-200, +-1e200, 1e300, NaN,
// inf, a copy of another vertex, a tiny offset), rewrite a face index (also out of range or
// negative), duplicate or drop a face. The result goes through validate_mesh() (and
// repair_mesh() first when asked), and if accepted, through the chosen method of the registry
// with few iterations. Allowed outcomes: InputError (the mesh is refused, naming why),
// NumericalError (a failed solve, named), or a finite form with the mesh's vertex count.
// Anything else - a crash, a sanitizer report, another exception, a NaN form - is a finding.
#include "canonform/canonical/method_registry.h"
#include "canonform/common/errors.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace {

using namespace canonform;
using namespace canonform::surface;
using namespace canonform::canonical;
using namespace canonform::procedural;

double hostile(std::uint8_t code, double base) {
    switch (code % 12) {
        case 0:
            return 0.0;
        case 1:
            return 1e-200;
        case 2:
            return -1e-200;
        case 3:
            return 1e200;
        case 4:
            return -1e200;
        case 5:
            return 1e300;
        case 6:
            return std::numeric_limits<double>::quiet_NaN();
        case 7:
            return std::numeric_limits<double>::infinity();
        case 8:
            return base * 1e-200;
        case 9:
            return base * 1e200;
        case 10:
            return base + 1e-12;
        default:
            return base * (1 + code / 256.0);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const Mesh bases[2] = {make_icosphere(0), make_icosphere(1)};
    const std::uint8_t head = data[0];
    Mesh m = bases[head & 1];
    const bool repair = (head >> 1) & 1;
    static const char* methods[] = {"none",          "euclidean-N", "euclidean-A", "geodesic-classical",
                                    "geodesic-fast", "geodesic-ls", "euclidean-N", "euclidean-N"};
    const char* method = methods[(head >> 2) & 7];
    std::vector<std::array<int, 3>> faces;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) faces.push_back({m.F(f, 0), m.F(f, 1), m.F(f, 2)});
    for (std::size_t at = 1; at + 8 <= size && at < 1 + 8 * 16; at += 8) {
        const std::uint8_t* e = data + at;
        const int nv = static_cast<int>(m.V.rows());
        switch (e[0] % 6) {
            case 0:  // a coordinate to a hostile value
                m.V(e[1] % nv, e[2] % 3) = hostile(e[3], m.V(e[1] % nv, e[2] % 3));
                break;
            case 1:  // a vertex onto another (duplicate vertex, zero-area faces)
                m.V.row(e[1] % nv) = m.V.row(e[2] % nv);
                break;
            case 2: {  // a face index to anything (also out of range or negative)
                if (faces.empty()) break;
                std::int32_t v;
                std::memcpy(&v, e + 4, 4);
                faces[e[1] % faces.size()][e[2] % 3] = (e[3] & 1) ? v : v % (nv + 2) - 1;
                break;
            }
            case 3:  // duplicate a face
                if (!faces.empty()) faces.push_back(faces[e[1] % faces.size()]);
                break;
            case 4:  // drop a face
                if (!faces.empty()) faces.erase(faces.begin() + e[1] % faces.size());
                break;
            default:  // a vertex far away (a second component if faces are rewired to it)
                m.V.row(e[1] % nv) *= (e[2] % 2 ? 1e3 : -1);
                break;
        }
    }
    m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (std::size_t f = 0; f < faces.size(); ++f)
        for (int c = 0; c < 3; ++c)
            m.F(static_cast<Eigen::Index>(f), c) = faces[f][static_cast<std::size_t>(c)];
    try {
        if (repair) m = repair_mesh(m.V, m.F).mesh;
        const MethodSpec spec = parse_method_spec(std::string(method) +
                                                  (std::strcmp(method, "none") ? ":max_iterations=30" : ""));
        MethodContext context;
        context.threads = 1;
        const CanonicalForm r = spec.method().run(m.V, m.F, spec.settings(), context);  // validates first
        if (r.V.rows() != m.V.rows() || !r.V.allFinite()) {
            std::fprintf(stderr, "fuzz: %s accepted the mesh and returned %s\n", method,
                         r.V.rows() != m.V.rows() ? "another vertex count" : "NaN or infinite coordinates");
            std::abort();
        }
    } catch (const InputError&) {
    } catch (const NumericalError&) {
    }
    return 0;
}
