// canonform tool: `canonform evaluate MATRIX --labels labels.csv [--json] [--pr PR.csv]`.
#pragma once

#include <string>

namespace canonform::cli {

/// Reads the distance matrix (binary float32 row-major, N from the file size, or a CSV file) and
/// the labels (CSV `path,class`, header optional, rows in matrix order), prints NN, first tier,
/// second tier, E-measure and DCG (micro and macro averages and per class, psbTable's
/// definitions), and writes the 20-point precision-recall curve to `pr_path` if given.
int evaluate_command(const std::string& matrix, const std::string& labels, bool json, const std::string& pr_path);

}  // namespace canonform::cli
