// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: precision-recall curves of retrieval runs on one plot - RUN/pr.png of `retrieve`
// and `canonform pr` (the paper's Figs. 10 and 11), drawn with Qt's painter: no Python, no file of
// the source tree.
#pragma once

#include <string>
#include <vector>

namespace canonform::cli {

/// One curve: a label and its points (recall, precision), in the file's order.
struct PrCurve {
    std::string label;
    std::vector<double> recall, precision;
};

/// The curve of every method folder of RUN that has a pr.csv (a "recall,precision" header, then
/// rows of two numbers in [0, 1], as `retrieve` and `evaluate --pr` write them), in the order of
/// the folders' names, each labelled "PREFIX FOLDER" (FOLDER when PREFIX is empty). Throws
/// InputError naming the file and the line on a malformed pr.csv, and naming RUN if it is no
/// folder.
std::vector<PrCurve> read_pr_curves(const std::string& run, const std::string& prefix = "");

/// Draws the curves into a PNG at `path`, written atomically: recall across and precision up, both
/// from 0 to 1 with grid lines every 0.2, one colour per curve (markers at the points), a legend
/// in the corner that hides the fewest points, and the title on top. Throws InputError if there is
/// no curve.
void write_pr_plot(const std::string& path, const std::vector<PrCurve>& curves, const std::string& title);

}  // namespace canonform::cli
