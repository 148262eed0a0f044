#include "canonform/io/distance_matrix_file.h"

#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/files.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace canonform::io {

void write_distance_matrix(const Eigen::MatrixXf& D, const std::string& bin_path, const std::string& csv_path) {
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> R = D;
    write_file_atomic(bin_path, std::string(reinterpret_cast<const char*>(R.data()), sizeof(float) * R.size()));
    std::ostringstream csv;
    csv.precision(7);
    for (Eigen::Index i = 0; i < D.rows(); ++i)
        for (Eigen::Index j = 0; j < D.cols(); ++j) csv << D(i, j) << (j + 1 < D.cols() ? "," : "\n");
    write_file_atomic(csv_path, csv.str());
}

Eigen::MatrixXd read_distance_matrix(const std::string& path) {
    const std::string bytes = read_file(path);
    if (lower_extension(path) == "csv") {
        const auto rows = parse_csv(bytes);
        Eigen::MatrixXd D(static_cast<Eigen::Index>(rows.size()),
                          rows.empty() ? 0 : static_cast<Eigen::Index>(rows[0].size()));
        for (size_t i = 0; i < rows.size(); ++i) {
            if (static_cast<Eigen::Index>(rows[i].size()) != D.cols())
                throw InputError("'" + path + "': rows of different lengths");
            for (size_t j = 0; j < rows[i].size(); ++j) {
                try {
                    D(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = std::stod(rows[i][j]);
                } catch (const std::exception&) {
                    throw InputError("'" + path + "': not a number: '" + rows[i][j] + "'");
                }
            }
        }
        return D;
    }
    const size_t count = bytes.size() / sizeof(float);
    const auto n = static_cast<Eigen::Index>(std::llround(std::sqrt(static_cast<double>(count))));
    if (bytes.size() % sizeof(float) != 0 || static_cast<size_t>(n * n) != count || n == 0)
        throw InputError("'" + path + "' is not a square float32 matrix (" + std::to_string(bytes.size()) + " bytes)");
    Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M(n, n);
    std::copy(bytes.data(), bytes.data() + bytes.size(), reinterpret_cast<char*>(M.data()));
    return M.cast<double>();
}

}  // namespace canonform::io
