// canonform tool: the view-descriptor commands (views, codebook, descriptor, distance).
#pragma once

#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

namespace canonform::cli {

/// Options shared by the view commands (parsed by main.cpp).
struct ViewCommandOptions {
    int image_size = 256;
    unsigned long long seed = 0;
    int words = 1500;
    bool random_codebook = false;
    std::string codebook;  ///< descriptor: codebook file ("" = raw SIFT features)
    int threads = 0;
    bool json = false;
};

/// Writes D as float32 row-major without header (`bin_path`, as the Princeton Shape Benchmark's
/// tools read it) and as CSV (`csv_path`), both atomically.
void write_distance_matrix(const Eigen::MatrixXf& D, const std::string& bin_path, const std::string& csv_path);

/// canonform views IN DIR: the 66 depth images as PNG and a contact sheet of them.
int views_command(const std::string& in, const std::string& dir, const ViewCommandOptions& o);
/// canonform codebook OUT MESH...: a codebook trained on the SIFT features of the meshes.
int codebook_command(const std::string& out, const std::vector<std::string>& meshes, const ViewCommandOptions& o);
/// canonform descriptor IN OUT [--codebook CB]: the descriptor file of one mesh.
int descriptor_command(const std::string& in, const std::string& out, const ViewCommandOptions& o);
/// canonform distance OUT DESC...: the clock-matching distance matrix (OUT: float32 row-major,
/// OUT.csv: text).
int distance_command(const std::string& out, const std::vector<std::string>& descriptors, const ViewCommandOptions& o);

}  // namespace canonform::cli
