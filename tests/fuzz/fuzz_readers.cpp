// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target of one reader of the project's files (chosen at compile time by
// CANONFORM_FUZZ_READER): the bytes are a file of that kind. A reader may refuse them - with an
// InputError, which names the cause - and must do nothing else: no crash, no sanitizer report, no
// other exception, no unbounded allocation (libFuzzer's -rss_limit_mb), no hang (-timeout); what
// it accepts must be consistent (checked below, abort otherwise). What a reader accepts also goes
// through the file functions around it: written with the writer to a file in a folder of this
// process (io::write_file_atomic, io::make_directories) and read back by path (io::read_file and
// the format from the extension), the same as the bytes.
//
//   mesh_off, mesh_ply, mesh_obj, mesh_stl   io::parse_mesh, then repair and validation of the mesh
//   descriptor                               views::parse_descriptor
//   codebook                                 views::Codebook::parse
//   matrix_bin, matrix_csv                   io::parse_distance_matrix
//   labels                                   io::parse_labels
#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
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

#include <unistd.h>

namespace {

using namespace canonform;
using namespace canonform::surface;

void require(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz: accepted input breaks an invariant: %s\n", what);
        std::abort();
    }
}

/// The folder for the file round trips: $CANONFORM_FUZZ_SCRATCH (run_fuzz.sh and fuzz_coverage.sh
/// name one in the build folder and remove it afterwards: libFuzzer ends without running atexit
/// handlers), else a folder of this process under /tmp.
[[maybe_unused]] const std::string& scratch() {
    static const std::string dir = [] {
        const char* env = std::getenv("CANONFORM_FUZZ_SCRATCH");
        const std::string d =
            env && *env ? std::string(env) : "/tmp/canonform-fuzz-" + std::to_string(::getpid());
        io::make_directories(d + "/sub");
        return d;
    }();
    return dir;
}

/// Equal values, NaN equal to NaN.
[[maybe_unused]] bool same(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
    for (Eigen::Index k = 0; k < a.size(); ++k)
        if (!(a.data()[k] == b.data()[k] || (std::isnan(a.data()[k]) && std::isnan(b.data()[k]))))
            return false;
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
        const io::MeshFile back = io::parse_mesh(
            io::format_mesh(out, m.V, m.F, q ? f.quality : Eigen::VectorXd()), out, "round trip");
        require(same(back.mesh.V, m.V) && back.mesh.F == m.F, "a written mesh reads back differently");
        require(!q || same(back.quality, f.quality), "written quality reads back differently");
    }
    // The same through files, by extension (write_mesh, write_ply, read_mesh_file, read_mesh,
    // read_ply_quality); STL holds float triangles, so only its face count is compared.
    if (m.V.rows() > 0) {
        const std::string base = scratch() + "/sub/m";
        io::write_mesh(base + ".off", m.V, m.F);
        require(same(io::read_mesh(base + ".off").V, m.V), "an OFF file reads back differently");
        io::write_ply(base + ".ply", m.V, m.F, f.quality);
        require(f.quality.size() == 0 || same(io::read_ply_quality(base + ".ply"), f.quality),
                "PLY file quality");
        io::write_mesh(base + ".obj", m.V, m.F);
        require(io::read_mesh_file(base + ".obj").mesh.F == m.F, "an OBJ file reads back differently");
        if (m.F.rows() > 0 && m.V.allFinite()) {
            io::write_mesh(base + ".stl", m.V, m.F);
            require(io::read_mesh_file(base + ".stl").mesh.F.rows() == m.F.rows(),
                    "an STL file's face count");
        }
        for (const char* bad : {".xyz", ""}) {
            try {
                (void)io::read_mesh(base + bad);
                require(false, "a mesh file without a known extension was read");
            } catch (const InputError&) {
            }
        }
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
            views::write_descriptor(scratch() + "/d.cfvd", d);
            const views::ModelDescriptor e = views::read_descriptor(scratch() + "/d.cfvd");
            require(e.keypoints_per_view == d.keypoints_per_view && e.views == d.views,
                    "a written descriptor reads back differently");
        }
        if (READER("codebook")) {
            const views::Codebook cb = views::Codebook::parse(bytes, "fuzz: ");
            require(cb.size() > 0 && cb.words().allFinite(), "codebook words");
            cb.save(scratch() + "/c.cfcb");
            require(views::Codebook::load(scratch() + "/c.cfcb").words() == cb.words(),
                    "a saved codebook loads differently");
        }
        if (READER("matrix_bin") || READER("matrix_csv")) {
            const Eigen::MatrixXd D = io::parse_distance_matrix(bytes, READER("matrix_csv"), "fuzz");
            require(D.rows() == D.cols() && D.rows() > 0 && D.allFinite(), "matrix");
            const Eigen::MatrixXf Df = D.cast<float>();
            io::write_distance_matrix(Df, scratch() + "/D.bin", scratch() + "/D.csv");
            require(io::read_distance_matrix(scratch() + "/D.bin") == Df.cast<double>(),
                    "a written matrix reads back differently");
            require(io::read_distance_matrix(scratch() + "/D.csv").rows() == D.rows(),
                    "a written CSV matrix");
        }
        if (READER("labels")) {
            const auto rows = io::parse_labels(bytes, "fuzz");
            for (const auto& r : rows) require(!r.label.empty(), "empty class accepted");
            io::write_file_atomic(scratch() + "/labels.csv", bytes);
            require(io::read_labels(scratch() + "/labels.csv").size() == rows.size(),
                    "labels read from a file");
            require(io::is_file(scratch() + "/labels.csv") && !io::is_file(scratch() + "/sub"), "is_file");
            (void)io::read_csv(scratch() + "/labels.csv");
        }
#undef READER
    } catch (const InputError&) {
        // refused with a reason: fine
    }
    return 0;
}
