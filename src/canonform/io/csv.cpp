#include "canonform/io/csv.h"

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
            cells.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        rows.push_back(std::move(cells));
    }
    return rows;
}

std::vector<std::vector<std::string>> read_csv(const std::string& path) { return parse_csv(read_file(path)); }

std::vector<LabelRow> read_labels(const std::string& path) {
    std::vector<LabelRow> out;
    for (const auto& cells : read_csv(path)) {
        LabelRow r;
        r.label = cells.back();
        for (size_t k = 0; k + 1 < cells.size(); ++k) r.path += (k ? "," : "") + cells[k];
        if (out.empty() && r.label == "class" && (r.path == "path" || r.path.empty())) continue;  // header
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace canonform::io
