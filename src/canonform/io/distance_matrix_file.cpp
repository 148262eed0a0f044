// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/io/distance_matrix_file.h"

#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/files.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace canonform::io {

void write_distance_matrix(const Eigen::MatrixXf& D, const std::string& bin_path,
                           const std::string& csv_path) {
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> R = D;
    write_file_atomic(bin_path,
                      std::string(reinterpret_cast<const char*>(R.data()), sizeof(float) * R.size()));
    std::ostringstream csv;
    csv.precision(7);
    for (Eigen::Index i = 0; i < D.rows(); ++i)
        for (Eigen::Index j = 0; j < D.cols(); ++j) csv << D(i, j) << (j + 1 < D.cols() ? "," : "\n");
    write_file_atomic(csv_path, csv.str());
}

Eigen::MatrixXd read_distance_matrix(const std::string& path) {
    return parse_distance_matrix(read_file(path), lower_extension(path) == "csv", path);
}

Eigen::MatrixXd parse_distance_matrix(const std::string& bytes, bool csv, const std::string& path) {
    const std::string where = "'" + path + "': ";
    Eigen::MatrixXd D;
    if (csv) {
        const auto rows = parse_csv(bytes);
        if (rows.empty()) throw InputError(where + "no rows (an empty distance matrix)");
        const size_t n = rows.size();
        for (size_t i = 0; i < n; ++i)
            if (rows[i].size() != n)
                throw InputError(where + "not a square matrix: row " + std::to_string(i + 1) + " has " +
                                 std::to_string(rows[i].size()) + " cells, the file " + std::to_string(n) +
                                 " rows");
        D.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
        for (size_t i = 0; i < n; ++i) {
            for (size_t j = 0; j < n; ++j) {
                const std::string& cell = rows[i][j];
                char* end = nullptr;
                const double v = cell.empty() ? 0.0 : std::strtod(cell.c_str(), &end);
                if (cell.empty() || end == cell.c_str() || *end != '\0')
                    throw InputError(where + "row " + std::to_string(i + 1) + ", column " +
                                     std::to_string(j + 1) + ": not a number: '" + cell.substr(0, 40) + "'");
                D(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = v;
            }
        }
    } else {
        const size_t count = bytes.size() / sizeof(float);
        const auto n = static_cast<Eigen::Index>(std::llround(std::sqrt(static_cast<double>(count))));
        if (bytes.size() % sizeof(float) != 0 || static_cast<size_t>(n) * static_cast<size_t>(n) != count ||
            n == 0)
            throw InputError(where + "not a square float32 matrix (" + std::to_string(bytes.size()) +
                             " bytes; N x N float32 is 4 N^2 bytes)");
        Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M(n, n);
        std::copy(bytes.data(), bytes.data() + bytes.size(), reinterpret_cast<char*>(M.data()));
        D = M.cast<double>();
    }
    for (Eigen::Index i = 0; i < D.rows(); ++i)
        for (Eigen::Index j = 0; j < D.cols(); ++j)
            if (!std::isfinite(D(i, j)))
                throw InputError(where + "entry (" + std::to_string(i + 1) + ", " + std::to_string(j + 1) +
                                 ") is not a finite number");
    return D;
}

}  // namespace canonform::io
