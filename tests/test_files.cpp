// io area: files and folders, CSV and label files, distance-matrix files, mesh files.
#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/procedural/procedural_meshes.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace canonform;
namespace fs = std::filesystem;

namespace {

/// A fresh folder under the test's temporary directory.
std::string scratch(const std::string& name) {
    const fs::path p = fs::temp_directory_path() / ("canonform_test_" + name);
    fs::remove_all(p);
    fs::create_directories(p);
    return p.string();
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(Files, AtomicWriteReadBackAndNoTemporaryLeft) {
    const std::string d = scratch("files");
    io::write_file_atomic(d + "/a.bin", std::string("x\0y", 3));
    EXPECT_EQ(io::read_file(d + "/a.bin"), std::string("x\0y", 3));
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 1);
    EXPECT_THROW(io::write_file_atomic(d + "/no/such/folder/a.bin", "x"), std::runtime_error);
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 1);
}

TEST(Files, ReadNamesTheRealCause) {
    const std::string d = scratch("causes");
    EXPECT_NE(message_of([&] { io::read_file(d + "/missing"); }).find("no such file"), std::string::npos);
    EXPECT_NE(message_of([&] { io::read_file(d); }).find("is a folder"), std::string::npos);
}

TEST(Files, FoldersAndExtensionsOfOddPaths) {
    const std::string d = scratch("v1.2");
    io::make_directories(d + "/x/y");
    EXPECT_TRUE(fs::is_directory(d + "/x/y"));
    EXPECT_EQ(io::lower_extension(d + "/D"), "");  // the folder's dot is not an extension
    EXPECT_EQ(io::lower_extension("a/B.PLY"), "ply");
    EXPECT_EQ(io::stem("/a/b.c/cat0.off"), "cat0");
    io::write_file_atomic(d + "/D", "1");  // no extension, in a folder with a dot
    EXPECT_EQ(io::read_file(d + "/D"), "1");
    EXPECT_THROW(io::make_directories(d + "/D/sub"), std::runtime_error);  // D is a file
}

TEST(Files, HashIsStableAndContentSensitive) {
    EXPECT_EQ(io::fnv1a(""), 1469598103934665603ULL);
    EXPECT_NE(io::fnv1a("ab"), io::fnv1a("ba"));
    EXPECT_EQ(io::hex(255), "00000000000000ff");
}

TEST(Csv, CellsRowsAndLabels) {
    const auto rows = io::parse_csv("a,b,,c\r\n\nd\n");
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0], (std::vector<std::string>{"a", "b", "", "c"}));
    EXPECT_EQ(rows[1], (std::vector<std::string>{"d"}));
    const std::string d = scratch("labels");
    io::write_file_atomic(d + "/l.csv", "path,class\noff/a,b.off,cat\nonly_class\n");
    const auto labels = io::read_labels(d + "/l.csv");
    ASSERT_EQ(labels.size(), 2u);
    EXPECT_EQ(labels[0].path, "off/a,b.off");  // the class is the last cell
    EXPECT_EQ(labels[0].label, "cat");
    EXPECT_EQ(labels[1].path, "");
    EXPECT_EQ(labels[1].label, "only_class");
}

TEST(DistanceMatrixFile, BinaryAndCsvRoundTripAndRefusals) {
    const std::string d = scratch("matrix");
    Eigen::MatrixXf D(3, 3);
    D << 0, 1.5f, 2, 1.5f, 0, 0.25f, 2, 0.25f, 0;
    io::write_distance_matrix(D, d + "/D.bin", d + "/D.csv");
    EXPECT_EQ(fs::file_size(d + "/D.bin"), 36u);
    EXPECT_TRUE(io::read_distance_matrix(d + "/D.bin").isApprox(D.cast<double>()));
    EXPECT_TRUE(io::read_distance_matrix(d + "/D.csv").isApprox(D.cast<double>()));
    io::write_file_atomic(d + "/bad.bin", std::string(20, '\0'));
    EXPECT_NE(message_of([&] { io::read_distance_matrix(d + "/bad.bin"); }).find("not a square"), std::string::npos);
    io::write_file_atomic(d + "/bad.csv", "0,1\n1\n");
    EXPECT_NE(message_of([&] { io::read_distance_matrix(d + "/bad.csv"); }).find("different lengths"),
              std::string::npos);
}

TEST(MeshIo, PlyOffObjRoundTrip) {
    const std::string d = scratch("meshes");
    const Mesh m = make_icosphere(2, 1.0);
    Eigen::VectorXd q = m.V.col(2);
    io::write_ply(d + "/s.ply", m.V, m.F, q);
    const Mesh r = io::read_mesh(d + "/s.ply");
    EXPECT_EQ(r.F, m.F);
    EXPECT_LT((r.V - m.V).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((io::read_ply_quality(d + "/s.ply") - q).cwiseAbs().maxCoeff(), 1e-12);
    std::string off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    io::write_file_atomic(d + "/t.off", off);
    EXPECT_EQ(io::read_mesh(d + "/t.off").F.rows(), 1);
    io::write_file_atomic(d + "/t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\n");
    const Mesh quad = io::read_mesh(d + "/t.obj");
    EXPECT_EQ(quad.F.rows(), 2);  // the quad fan-triangulated
    EXPECT_THROW(io::read_mesh(d + "/missing.ply"), InputError);
}
