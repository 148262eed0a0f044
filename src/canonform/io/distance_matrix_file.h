// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: distance-matrix files, as the Princeton Shape Benchmark's tools read them.
//
// Binary: N x N float32, row-major, native (little-endian) byte order, no header: the file size
// is 4 N^2 bytes. Text: N lines of N comma-separated numbers.
#pragma once

#include <Eigen/Core>

#include <string>

namespace canonform::io {

/// Writes D as binary (`bin_path`) and as CSV (`csv_path`, 7 significant digits), both atomically.
void write_distance_matrix(const Eigen::MatrixXf& D, const std::string& bin_path,
                           const std::string& csv_path);

/// Reads a distance matrix: CSV if the name ends in .csv, else binary. InputError naming the file
/// and the cause (missing, a folder, empty, not square, a cell that is not a number, a NaN or
/// infinite entry).
Eigen::MatrixXd read_distance_matrix(const std::string& path);

/// Parses the bytes of a distance-matrix file (CSV text if `csv`, else binary) as
/// read_distance_matrix(); `path` names it in messages.
Eigen::MatrixXd parse_distance_matrix(const std::string& bytes, bool csv, const std::string& path);

}  // namespace canonform::io
