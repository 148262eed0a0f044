// SPDX-License-Identifier: GPL-3.0-or-later
// io area: files and folders, CSV and label files, distance-matrix files, mesh files.
#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/procedural/procedural_meshes.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <limits>

using namespace canonform;
namespace fs = std::filesystem;
using canonform::test::message_of;
using canonform::test::scratch_dir;

TEST(Files, AtomicWriteReadBackAndNoTemporaryLeft) {
    const std::string d = scratch_dir("files");
    io::write_file_atomic(d + "/a.bin", std::string("x\0y", 3));
    EXPECT_EQ(io::read_file(d + "/a.bin"), std::string("x\0y", 3));
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 1);
    EXPECT_THROW(io::write_file_atomic(d + "/no/such/folder/a.bin", "x"), std::runtime_error);
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 1);
}

TEST(Files, ReadNamesTheRealCause) {
    const std::string d = scratch_dir("causes");
    EXPECT_NE(message_of([&] { io::read_file(d + "/missing"); }).find("no such file"), std::string::npos);
    EXPECT_NE(message_of([&] { io::read_file(d); }).find("is a folder"), std::string::npos);
}

TEST(Files, FoldersAndExtensionsOfOddPaths) {
    const std::string d = scratch_dir("v1.2");
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
    const std::string d = scratch_dir("labels");
    io::write_file_atomic(d + "/l.csv", "path,class\noff/a,b.off,cat\nonly_class\n");
    const auto labels = io::read_labels(d + "/l.csv");
    ASSERT_EQ(labels.size(), 2u);
    EXPECT_EQ(labels[0].path, "off/a,b.off");  // the class is the last cell
    EXPECT_EQ(labels[0].label, "cat");
    EXPECT_EQ(labels[1].path, "");
    EXPECT_EQ(labels[1].label, "only_class");
}

TEST(DistanceMatrixFile, BinaryAndCsvRoundTripAndRefusals) {
    const std::string d = scratch_dir("matrix");
    Eigen::MatrixXf D(3, 3);
    D << 0, 1.5f, 2, 1.5f, 0, 0.25f, 2, 0.25f, 0;
    io::write_distance_matrix(D, d + "/D.bin", d + "/D.csv");
    EXPECT_EQ(fs::file_size(d + "/D.bin"), 36u);
    EXPECT_TRUE(io::read_distance_matrix(d + "/D.bin").isApprox(D.cast<double>()));
    EXPECT_TRUE(io::read_distance_matrix(d + "/D.csv").isApprox(D.cast<double>()));
    io::write_file_atomic(d + "/bad.bin", std::string(20, '\0'));
    EXPECT_NE(message_of([&] { io::read_distance_matrix(d + "/bad.bin"); }).find("not a square"),
              std::string::npos);
    io::write_file_atomic(d + "/bad.csv", "0,1\n1\n");
    EXPECT_NE(message_of([&] { io::read_distance_matrix(d + "/bad.csv"); }).find("not a square"),
              std::string::npos);
}

TEST(Files, EveryReaderSaysAFolderIsAFolder) {
    // Issue 11: a folder given as a matrix or labels file was "truncated, 0 bytes".
    const std::string d = scratch_dir("folder_inputs");
    io::make_directories(d + "/D.bin");
    io::make_directories(d + "/D.csv");
    io::make_directories(d + "/labels.csv");
    for (const std::string& m : {message_of([&] { io::read_distance_matrix(d + "/D.bin"); }),
                                 message_of([&] { io::read_distance_matrix(d + "/D.csv"); }),
                                 message_of([&] { io::read_labels(d + "/labels.csv"); })})
        EXPECT_NE(m.find("is a folder"), std::string::npos) << m;
}

TEST(Csv, LabelsRefuseRowsWithoutAClassAndEmptyFiles) {
    EXPECT_NE(
        message_of([] { io::parse_labels("path,class\na.off,\n", "l.csv"); }).find("row 2 has no class"),
        std::string::npos);
    EXPECT_NE(message_of([] { io::parse_labels("path,class\n", "l.csv"); }).find("no labels"),
              std::string::npos);
    EXPECT_EQ(io::parse_labels("a.off,\"q\\\"x\n", "l.csv")[0].label,
              "\"q\\\"x");  // any bytes are a class name
    test::fuzz_seed("labels", "header_and_rows.csv",
                    "path,class\noff/a,b.off,cat\nonly_class\nx.off,dog\r\n");
    test::fuzz_seed("labels", "no_class.csv", "path,class\na.off,\n");
}

TEST(DistanceMatrixFile, RefusesNonNumbersAndNonFiniteEntries) {
    EXPECT_NE(message_of([] {
                  io::parse_distance_matrix("0,1x\n1,0\n", true, "D.csv");
              }).find("not a number: '1x'"),
              std::string::npos);
    EXPECT_NE(
        message_of([] { io::parse_distance_matrix("0,nan\n1,0\n", true, "D.csv"); }).find("not a finite"),
        std::string::npos);
    EXPECT_NE(message_of([] { io::parse_distance_matrix("", true, "D.csv"); }).find("no rows"),
              std::string::npos);
    const float bad[4] = {0, std::numeric_limits<float>::infinity(), 1, 0};
    const std::string bytes(reinterpret_cast<const char*>(bad), sizeof bad);
    EXPECT_NE(
        message_of([&] { io::parse_distance_matrix(bytes, false, "D.bin"); }).find("(1, 2) is not a finite"),
        std::string::npos);
    const float good[9] = {0, 1, 2, 1, 0, 3, 2, 3, 0};
    test::fuzz_seed("matrix_bin", "3x3.bin", std::string(reinterpret_cast<const char*>(good), sizeof good));
    test::fuzz_seed("matrix_bin", "inf.bin", bytes);
    test::fuzz_seed("matrix_csv", "3x3.csv", "0,1,2\n1,0,3\n2,3,0\n");
    test::fuzz_seed("matrix_csv", "ragged.csv", "0,1\n1\n");
}
