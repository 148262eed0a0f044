// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target of one reader of the project's files (chosen at compile time by
// CANONFORM_FUZZ_READER): the bytes are a file of that kind. A reader may refuse them - with an
// InputError, which names the cause - and must do nothing else: no crash, no sanitizer report, no
// other exception, no unbounded allocation (libFuzzer's -rss_limit_mb), no hang (-timeout); what
// it accepts must be consistent (checked below, abort otherwise).
//
//   mesh_off, mesh_ply, mesh_obj, mesh_stl   io::parse_mesh, then repair and validation of the mesh
//   descriptor                               views::parse_descriptor
//   codebook                                 views::Codebook::parse
//   matrix_bin, matrix_csv                   io::parse_distance_matrix
//   labels                                   io::parse_labels
#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/mesh_io.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/views/codebook.h"
#include "canonform/views/descriptor_file.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

using namespace canonform;
using namespace canonform::surface;

void require(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz: accepted input breaks an invariant: %s\n", what);
        std::abort();
    }
}

/// Equal values, NaN equal to NaN.
[[maybe_unused]] bool same(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
    for (Eigen::Index k = 0; k < a.size(); ++k)
        if (!(a.data()[k] == b.data()[k] || (std::isnan(a.data()[k]) && std::isnan(b.data()[k])))) return false;
    return true;
}

[[maybe_unused]] void check_mesh(const io::MeshFile& f) {
    const Mesh& m = f.mesh;
    require(m.V.cols() == 3 && (m.F.rows() == 0 || m.F.cols() == 3), "shapes");
    for (Eigen::Index k = 0; k < m.F.size(); ++k)
        require(m.F.data()[k] >= 0 && m.F.data()[k] < m.V.rows(), "a face index out of range was accepted");
    require(f.quality.size() == 0 || f.quality.size() == m.V.rows(), "quality size");
    // What is accepted is written back and read again unchanged (PLY binary, OFF and OBJ text keep
    // doubles exactly; STL stores floats, so it is not in the loop; OBJ cannot hold no vertices).
    for (const io::MeshFormat out : {io::MeshFormat::Ply, io::MeshFormat::Off, io::MeshFormat::Obj}) {
        if (out == io::MeshFormat::Obj && m.V.rows() == 0) continue;
        const bool q = out == io::MeshFormat::Ply && f.quality.size() > 0;
        const io::MeshFile back =
            io::parse_mesh(io::format_mesh(out, m.V, m.F, q ? f.quality : Eigen::VectorXd()), out, "round trip");
        require(same(back.mesh.V, m.V) && back.mesh.F == m.F, "a written mesh reads back differently");
        require(!q || same(back.quality, f.quality), "written quality reads back differently");
    }
    // What a command does next with a mesh it read: (repair and) validate; `canonform check` lists
    // every problem instead (it must agree with validate_mesh about whether there is one).
    bool valid = true;
    try {
        validate_mesh(m.V, m.F);
    } catch (const InputError&) {
        valid = false;
    }
    require(mesh_problems(m.V, m.F).empty() == valid, "mesh_problems() and validate_mesh() disagree");
    try {
        const MeshRepair r = repair_mesh(m.V, m.F);
        for (Eigen::Index k = 0; k < r.mesh.F.size(); ++k)
            require(r.mesh.F.data()[k] >= 0 && r.mesh.F.data()[k] < r.mesh.V.rows(), "repair broke an index");
        require(static_cast<Eigen::Index>(r.vertex_source.size()) == r.mesh.V.rows(), "repair vertex map");
        require(static_cast<Eigen::Index>(r.face_source.size()) == r.mesh.F.rows(), "repair face map");
        validate_mesh(r.mesh.V, r.mesh.F);
    } catch (const InputError&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
#define READER(x) (std::strcmp(CANONFORM_FUZZ_READER, x) == 0)
        // Each mesh reader twice: strict, and dropping faces with indices out of range (`check --repair`).
        const auto mesh = [&](io::MeshFormat format, const char* name) {
            for (const bool drop : {false, true}) {
                io::ReadOptions o;
                o.drop_bad_faces = drop;
                try {
                    const io::MeshFile f = io::parse_mesh(bytes, format, name, o);
                    require(drop || f.dropped_faces == 0, "a strict read dropped faces");
                    check_mesh(f);
                } catch (const InputError&) {
                }
            }
        };
        if (READER("mesh_off")) mesh(io::MeshFormat::Off, "fuzz.off");
        if (READER("mesh_ply")) mesh(io::MeshFormat::Ply, "fuzz.ply");
        if (READER("mesh_obj")) mesh(io::MeshFormat::Obj, "fuzz.obj");
        if (READER("mesh_stl")) mesh(io::MeshFormat::Stl, "fuzz.stl");
        if (READER("descriptor")) {
            const views::ModelDescriptor d = views::parse_descriptor(bytes, "fuzz: ");
            require(static_cast<int>(d.keypoints_per_view.size()) == d.views, "descriptor views");
        }
        if (READER("codebook")) {
            const views::Codebook cb = views::Codebook::parse(bytes, "fuzz: ");
            require(cb.size() > 0 && cb.words().allFinite(), "codebook words");
        }
        if (READER("matrix_bin") || READER("matrix_csv")) {
            const Eigen::MatrixXd D = io::parse_distance_matrix(bytes, READER("matrix_csv"), "fuzz");
            require(D.rows() == D.cols() && D.rows() > 0 && D.allFinite(), "matrix");
        }
        if (READER("labels")) {
            const auto rows = io::parse_labels(bytes, "fuzz");
            for (const auto& r : rows) require(!r.label.empty(), "empty class accepted");
        }
#undef READER
    } catch (const InputError&) {
        // refused with a reason: fine
    }
    return 0;
}
