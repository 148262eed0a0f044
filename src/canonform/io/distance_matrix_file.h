// canonform: distance-matrix files, as the Princeton Shape Benchmark's tools read them.
//
// Binary: N x N float32, row-major, native (little-endian) byte order, no header: the file size
// is 4 N^2 bytes. Text: N lines of N comma-separated numbers.
#pragma once

#include <Eigen/Core>

#include <string>

namespace canonform::io {

/// Writes D as binary (`bin_path`) and as CSV (`csv_path`, 7 significant digits), both atomically.
void write_distance_matrix(const Eigen::MatrixXf& D, const std::string& bin_path, const std::string& csv_path);

/// Reads a distance matrix: CSV if the name ends in .csv, else binary. InputError naming the file
/// and the cause (not square, rows of different lengths, a cell that is not a number).
Eigen::MatrixXd read_distance_matrix(const std::string& path);

}  // namespace canonform::io
