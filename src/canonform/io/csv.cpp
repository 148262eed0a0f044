// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/io/csv.h"

#include "canonform/common/errors.h"
#include "canonform/io/files.h"

#include <sstream>

namespace canonform::io {

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        std::vector<std::string> cells;
        std::string::size_type start = 0;
        for (;;) {
            const auto comma = line.find(',', start);
            cells.push_back(
                line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        rows.push_back(std::move(cells));
    }
    return rows;
}

std::vector<std::vector<std::string>> read_csv(const std::string& path) {
    return parse_csv(read_file(path));
}

std::vector<LabelRow> read_labels(const std::string& path) {
    return parse_labels(read_file(path), path);
}

std::vector<LabelRow> parse_labels(const std::string& text, const std::string& path) {
    std::vector<LabelRow> out;
    const auto rows = parse_csv(text);
    for (size_t k = 0; k < rows.size(); ++k) {
        const auto& cells = rows[k];
        LabelRow r;
        r.label = cells.back();
        for (size_t c = 0; c + 1 < cells.size(); ++c) r.path += (c ? "," : "") + cells[c];
        if (k == 0 && r.label == "class" && (r.path == "path" || r.path.empty())) continue;  // header
        if (r.label.empty())
            throw InputError("'" + path + "': row " + std::to_string(k + 1) +
                             " has no class (rows are path,class)");
        out.push_back(std::move(r));
    }
    if (out.empty()) throw InputError("'" + path + "': no labels (rows are path,class)");
    return out;
}

}  // namespace canonform::io
