// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the project's comma-separated files - labels, collections, matrices as text.
//
// Plain CSV without quoting (the files the project reads and writes have none): cells are split
// at commas, a trailing CR is dropped, empty lines are skipped.
#pragma once

#include <string>
#include <vector>

namespace canonform::io {

/// Rows of cells of a CSV text.
std::vector<std::vector<std::string>> parse_csv(const std::string& text);

/// Rows of cells of a CSV file (InputError naming the file if it cannot be read).
std::vector<std::vector<std::string>> read_csv(const std::string& path);

/// One row of a labels file: a model's path (may be empty) and its class.
struct LabelRow {
    std::string path;
    std::string label;
};

/// A labels file: rows "path,class" (the class is the last cell, the path the cells before it; a
/// row of one cell is a class alone), in order; a first row with class "class" is a header and
/// skipped. InputError naming the file if it cannot be read, has no rows, or a row has an empty
/// class.
std::vector<LabelRow> read_labels(const std::string& path);

/// The labels of a labels file's text (as read_labels(); `path` names it in messages).
std::vector<LabelRow> parse_labels(const std::string& text, const std::string& path);

}  // namespace canonform::io
