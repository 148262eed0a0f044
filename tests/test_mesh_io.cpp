// SPDX-License-Identifier: GPL-3.0-or-later
// io/mesh_io.h: the four formats in and out, and every way a mesh file can be broken or hostile
// (issue 11): each refused with an InputError naming the cause, before any allocation or use.
// The files built here are also the seeds of the mesh fuzz targets (tests/fuzz).
#include "canonform/common/errors.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/procedural/procedural_meshes.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>

using namespace canonform;
using namespace canonform::procedural;
using canonform::test::fuzz_seed;
using canonform::test::message_of;
namespace fs = std::filesystem;

namespace {

/// The message of parsing `bytes` as `format` ("" if it parses).
std::string refusal(const std::string& bytes, io::MeshFormat format) {
    return message_of([&] { io::parse_mesh(bytes, format, "m"); });
}

const char* seed_target(io::MeshFormat f) {
    switch (f) {
        case io::MeshFormat::Off:
            return "mesh_off";
        case io::MeshFormat::Ply:
            return "mesh_ply";
        case io::MeshFormat::Obj:
            return "mesh_obj";
        case io::MeshFormat::Stl:
            return "mesh_stl";
    }
    return "";
}

/// 12 vertices on a line-free spiral and 20 fan faces, as OFF text with face `bad` replaced.
std::string off_text(const std::string& bad_face, const std::string& counts = "12 12 0") {
    std::string s = "OFF\n" + counts + "\n";
    for (int k = 0; k < 12; ++k)
        s += std::to_string(k) + " " + std::to_string(k * k % 7) + " " + std::to_string(k % 4) + "\n";
    s += bad_face + "\n";
    for (int k = 1; k < 12; ++k)
        s += "3 " + std::to_string(k) + " " + std::to_string((k + 1) % 12) + " " +
             std::to_string((k + 2) % 12) + "\n";
    return s;
}

template <class T>
void put(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
}

}  // namespace

TEST(MeshIo, EveryFormatRoundTrips) {
    const std::string d = test::scratch_dir("mesh_formats");
    const Mesh m = make_icosphere(2, 1.0);
    const Eigen::VectorXd q = m.V.col(2);
    for (const char* ext : {"ply", "off", "obj", "stl"}) {
        const std::string path = d + "/s." + ext;
        io::write_mesh(path, m.V, m.F, q);
        const io::MeshFile r = io::read_mesh_file(path);
        ASSERT_EQ(r.mesh.V.rows(), m.V.rows()) << ext;  // STL: equal corners merged back
        ASSERT_EQ(r.mesh.F.rows(), m.F.rows()) << ext;
        double worst = 0;  // STL numbers vertices in order of first use: compare corner by corner
        for (Eigen::Index f = 0; f < m.F.rows(); ++f)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst,
                                 (r.mesh.V.row(r.mesh.F(f, c)) - m.V.row(m.F(f, c))).cwiseAbs().maxCoeff());
        EXPECT_LT(worst, std::string(ext) == "stl" ? 1e-6 : 1e-15) << ext;  // STL stores float
        if (std::string(ext) != "stl") {
            EXPECT_EQ(r.mesh.F, m.F) << ext;
        }
        if (std::string(ext) == "ply") {
            EXPECT_LT((r.quality - q).cwiseAbs().maxCoeff(), 1e-15);
        }
        fuzz_seed(seed_target(io::input_mesh_format(path)), std::string("icosphere.") + ext,
                  io::read_file(path));
    }
    // A quad and a pentagon fan-triangulated; OBJ's i/t/n and negative (relative) indices.
    io::write_file_atomic(d + "/t.obj",
                          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1/1 2//3 3/1/2 4\nf -1 -2 -3\n");
    EXPECT_EQ(io::read_mesh(d + "/t.obj").F.rows(), 3);
    const std::string off = "OFF\n# a comment\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n-1 0.5 0\n5 0 1 2 3 4\n";
    EXPECT_EQ(io::parse_mesh(off, io::MeshFormat::Off, "p.off").mesh.F.rows(), 3);
    fuzz_seed("mesh_off", "pentagon.off", off);
    fuzz_seed("mesh_obj", "quad.obj", io::read_file(d + "/t.obj"));
}

TEST(MeshIo, ReadsThePlyVariantsMeshLabAndOthersWrite) {
    // ASCII with normals, colours, flags, float quality and an extra element.
    const std::string ascii =
        "ply\r\nformat ascii 1.0\r\ncomment by MeshLab\r\nelement vertex 3\r\nproperty float x\r\nproperty "
        "float y\r\n"
        "property float z\r\nproperty float nx\r\nproperty float ny\r\nproperty float nz\r\nproperty uchar "
        "red\r\n"
        "property uchar green\r\nproperty uchar blue\r\nproperty uchar alpha\r\nproperty float quality\r\n"
        "element face 1\r\nproperty list uchar int vertex_indices\r\nproperty int flags\r\nelement edge 0\r\n"
        "property int vertex1\r\nend_header\r\n"
        "0 0 0 0 0 1 255 0 0 255 0.5\r\n1 0 0 0 0 1 0 255 0 255 1\r\n0 1 0 0 0 1 0 0 255 255 -2\r\n3 0 1 2 "
        "0\r\n";
    const io::MeshFile a = io::parse_mesh(ascii, io::MeshFormat::Ply, "a.ply");
    EXPECT_EQ(a.mesh.V.rows(), 3);
    EXPECT_EQ(a.mesh.F.rows(), 1);
    EXPECT_EQ(a.quality(2), -2);
    // Big-endian binary with a uint vertex_index list and short coordinates.
    std::string big =
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty short x\nproperty short y\n"
        "property short z\nelement face 1\nproperty list uint uint vertex_index\nend_header\n";
    for (std::uint16_t v : {0, 0, 0, 1, 0, 0, 0, 1, 0}) big += std::string{char(v >> 8), char(v & 255)};
    for (std::uint32_t v : {3u, 0u, 1u, 2u})
        big += std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    const Mesh b = io::parse_mesh(big, io::MeshFormat::Ply, "b.ply").mesh;
    EXPECT_EQ(b.V(1, 0), 1);
    EXPECT_EQ(b.F.row(0), Eigen::RowVector3i(0, 1, 2));
    fuzz_seed("mesh_ply", "ascii_meshlab.ply", ascii);
    fuzz_seed("mesh_ply", "big_endian.ply", big);
}

TEST(MeshIo, FaceIndicesOutOfRangeAreRefusedBeforeUse) {
    // Issue 11: "3 0 100000000 10" in a 12-vertex OFF made every command segfault; an index equal
    // to #V or -1 was an out-of-bounds read blamed on "non-manifold edges".
    for (const std::string face : {"3 0 100000000 10", "3 0 12 10", "3 0 -1 10"}) {
        const std::string off = off_text(face);
        const std::string m = refusal(off, io::MeshFormat::Off);
        EXPECT_NE(m.find("out of range: the file has 12 vertices"), std::string::npos) << m;
        fuzz_seed("mesh_off", "bad_index_" + std::to_string(std::hash<std::string>()(face) % 1000) + ".off",
                  off);
    }
    const std::string ply_head =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n";
    for (const std::string face : {"3 0 1 3", "3 0 -1 2", "3 0 1 2.5"}) {
        const std::string m = refusal(ply_head + face + "\n", io::MeshFormat::Ply);
        EXPECT_TRUE(m.find("out of range") != std::string::npos ||
                    m.find("not a whole number") != std::string::npos)
            << m;
        fuzz_seed("mesh_ply", "bad_index_" + std::to_string(face.size() + face[6]) + ".ply",
                  ply_head + face + "\n");
    }
    std::string bin =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(bin, v);
    put(bin, std::uint8_t(3));
    for (std::int32_t v : {0, 1, 100000000}) put(bin, v);
    EXPECT_NE(refusal(bin, io::MeshFormat::Ply).find("face index 100000000 in face 0 is out of range"),
              std::string::npos);
    fuzz_seed("mesh_ply", "bad_index_binary.ply", bin);
    for (const std::string obj :
         {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
          "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n"}) {
        EXPECT_FALSE(refusal(obj, io::MeshFormat::Obj).empty()) << obj;
        fuzz_seed("mesh_obj", "bad_index_" + std::to_string(obj[obj.size() - 6]) + ".obj", obj);
    }
}

TEST(MeshIo, AHeaderThatLiesIsRefusedBeforeAllocating) {
    // Issue 11: a 959-byte OFF claiming 40 million vertices took 2.5 GB; 2e9 gave std::bad_alloc.
    const auto t0 = std::chrono::steady_clock::now();
    for (const std::string counts :
         {"40000000 12 0", "2000000000 12 0", "12 40000000 0", "9000000000000000000 1 0"}) {
        const std::string m = refusal(off_text("3 0 1 2", counts), io::MeshFormat::Off);
        EXPECT_NE(m.find("the header lies"), std::string::npos) << m;
        fuzz_seed("mesh_off", "lying_header_" + std::to_string(counts.size()) + ".off",
                  off_text("3 0 1 2", counts));
    }
    const std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 40000000\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n" +
        std::string(959, '\0');
    EXPECT_NE(refusal(ply, io::MeshFormat::Ply).find("claims 40000000 'vertex' elements"), std::string::npos);
    fuzz_seed("mesh_ply", "lying_header.ply", ply);
    // A list whose length claims more than the file holds.
    std::string list =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
    for (int k = 0; k < 9; ++k) put(list, 0.5f * static_cast<float>(k % 3));
    put(list, std::uint32_t(4000000000u));
    EXPECT_NE(refusal(list, io::MeshFormat::Ply).find("more than the rest of the file holds"),
              std::string::npos);
    fuzz_seed("mesh_ply", "lying_list.ply", list);
    // An ASCII list count beyond any integer type (found by fuzz_mesh_ply: the message converted it
    // to an unsigned 64-bit integer, undefined behaviour), and one that is infinite.
    for (const auto& [count, expected] : std::vector<std::pair<std::string, std::string>>{
             {"22222222222222222222222223", "claims 22222222222222221849395200 entries"},
             {"1e400", "bad list length"}}) {
        const std::string ascii =
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0\n1 0 0\n0 1 0\n" +
            count + " 0 1 2\n";
        const std::string m = refusal(ascii, io::MeshFormat::Ply);
        EXPECT_NE(m.find(expected), std::string::npos) << m;
        fuzz_seed("mesh_ply", "huge_ascii_list_" + std::to_string(count.size()) + ".ply", ascii);
    }
    // Binary STL: 80-byte header, a count of 40 million triangles, one triangle of data.
    std::string stl(80, 'x');
    put(stl, std::uint32_t(40000000));
    stl += std::string(50, '\0');
    EXPECT_NE(refusal(stl, io::MeshFormat::Stl).find("claims 40000000 triangles"), std::string::npos);
    fuzz_seed("mesh_stl", "lying_count.stl", stl);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(seconds, 5.0);  // nothing of the claimed size was allocated or touched
}

TEST(MeshIo, OtherBrokenFilesNameTheirCause) {
    const std::string d = test::scratch_dir("mesh_causes");
    io::write_file_atomic(d + "/empty.off", "");
    EXPECT_NE(message_of([&] { io::read_mesh(d + "/empty.off"); }).find("the file is empty"),
              std::string::npos);
    EXPECT_NE(message_of([&] { io::read_mesh(d + "/missing.ply"); }).find("no such file"), std::string::npos);
    io::make_directories(d + "/folder.off");
    EXPECT_NE(message_of([&] { io::read_mesh(d + "/folder.off"); }).find("is a folder"), std::string::npos);
    io::write_file_atomic(d + "/x.png", "x");
    EXPECT_NE(message_of([&] { io::read_mesh(d + "/x.png"); }).find("unsupported format '.png'"),
              std::string::npos);
    const Mesh m = make_icosphere(1);
    io::write_mesh(d + "/ply_named.ply", m.V, m.F);
    fs::copy_file(d + "/ply_named.ply", d + "/ply_named.off");
    EXPECT_NE(message_of([&] { io::read_mesh(d + "/ply_named.off"); }).find("starts like a PLY file"),
              std::string::npos);
    EXPECT_NE(refusal("OFF\n3 1 0\n0 0 0\n1 0 0\n", io::MeshFormat::Off).find("truncated"),
              std::string::npos);
    EXPECT_NE(refusal("OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", io::MeshFormat::Off)
                  .find("bad vertex on line 4"),
              std::string::npos);
    EXPECT_NE(refusal("4OFF\n1 0 0\n0 0 0 0\n", io::MeshFormat::Off).find("not supported"),
              std::string::npos);
    EXPECT_NE(refusal("ply\nformat ascii 1.0\nend_header\n", io::MeshFormat::Ply).find("no vertex element"),
              std::string::npos);
    EXPECT_NE(refusal("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n",
                      io::MeshFormat::Stl)
                  .find("a facet of 2 vertices"),
              std::string::npos);
    EXPECT_NE(refusal("# nothing\n", io::MeshFormat::Obj).find("no vertices"), std::string::npos);
    // NaN and huge coordinates are read as written: validate_mesh() names them.
    const Mesh nan =
        io::parse_mesh("OFF\n3 1 0\nnan 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n", io::MeshFormat::Off, "n.off").mesh;
    EXPECT_TRUE(std::isnan(nan.V(0, 0)));
    EXPECT_TRUE(std::isinf(nan.V(1, 0)));
    const std::string ascii_stl =
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
        "endloop\nendfacet\nendsolid t\n";
    EXPECT_EQ(io::parse_mesh(ascii_stl, io::MeshFormat::Stl, "t.stl").mesh.F.rows(), 1);
    fuzz_seed("mesh_stl", "ascii.stl", ascii_stl);
    fuzz_seed("mesh_off", "nan.off", "OFF\n3 1 0\nnan 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n");
}

TEST(MeshIo, AnOutputIsWrittenInTheFormatItsNameSaysOrRefused) {
    // Issue 11: "out.off" and "out.obj" were binary PLY under that name; an output without an
    // extension in a folder with a dot ("/data/v1.2/D") failed with "cannot write".
    const std::string d = test::scratch_dir("v1.2");
    const Mesh m = make_icosphere(1);
    io::write_mesh(d + "/out.off", m.V, m.F);
    io::write_mesh(d + "/out.obj", m.V, m.F);
    io::write_mesh(d + "/out.STL", m.V, m.F);
    io::write_mesh(d + "/D", m.V, m.F);
    EXPECT_EQ(io::read_file(d + "/out.off").substr(0, 4), "OFF\n");
    EXPECT_EQ(io::read_file(d + "/out.obj").substr(0, 1), "#");
    EXPECT_EQ(io::read_file(d + "/out.STL").substr(0, 9), "canonform");
    EXPECT_EQ(io::read_file(d + "/D").substr(0, 4), "ply\n");
    EXPECT_EQ(io::parse_mesh(io::read_file(d + "/D"), io::MeshFormat::Ply, "D").mesh.F, m.F);
    EXPECT_NE(message_of([&] { io::write_ply(d + "/p.off", m.V, m.F); }).find("a PLY file under a .off name"),
              std::string::npos);
    EXPECT_NE(
        message_of([&] { io::write_mesh(d + "/p.xyz", m.V, m.F); }).find("unsupported mesh format '.xyz'"),
        std::string::npos);
    EXPECT_NE(
        message_of([&] { io::write_mesh(d + "/p.stl", m.V, Eigen::MatrixXi(0, 3)); }).find("point cloud"),
        std::string::npos);
    Eigen::MatrixXi bad = m.F;
    bad(0, 0) = static_cast<int>(m.V.rows());
    EXPECT_NE(message_of([&] { io::write_mesh(d + "/p.ply", m.V, bad); }).find("out of range"),
              std::string::npos);
    EXPECT_FALSE(fs::exists(d + "/p.off") || fs::exists(d + "/p.xyz") || fs::exists(d + "/p.stl") ||
                 fs::exists(d + "/p.ply"));
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 4);  // no temporary left
}
