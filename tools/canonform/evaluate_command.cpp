#include "evaluate_command.h"

#include "canonform/retrieval/retrieval_measures.h"
#include "canonform/io/mesh_io.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

namespace canonform::cli {

namespace {

Eigen::MatrixXd read_matrix(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string bytes = ss.str();
    if (path.size() > 4 && path.substr(path.size() - 4) == ".csv") {
        std::vector<std::vector<double>> rows;
        std::istringstream text(bytes);
        std::string line;
        while (std::getline(text, line)) {
            if (line.empty()) continue;
            std::vector<double> r;
            std::istringstream ls(line);
            std::string cell;
            while (std::getline(ls, cell, ',')) {
                try {
                    r.push_back(std::stod(cell));
                } catch (const std::exception&) {
                    throw InputError("'" + path + "': not a number: '" + cell + "'");
                }
            }
            rows.push_back(r);
        }
        Eigen::MatrixXd D(static_cast<Eigen::Index>(rows.size()), rows.empty() ? 0 : static_cast<Eigen::Index>(rows[0].size()));
        for (size_t i = 0; i < rows.size(); ++i) {
            if (static_cast<Eigen::Index>(rows[i].size()) != D.cols()) throw InputError("'" + path + "': rows of different lengths");
            for (size_t j = 0; j < rows[i].size(); ++j) D(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
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

std::vector<std::string> read_labels(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError("cannot read '" + path + "'");
    std::vector<std::string> labels;
    std::string line;
    bool first = true;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        const auto comma = line.rfind(',');
        const std::string cls = comma == std::string::npos ? line : line.substr(comma + 1);
        if (first && cls == "class") {
            first = false;
            continue;  // header
        }
        first = false;
        labels.push_back(cls);
    }
    return labels;
}

void print_row(std::ostream& o, const std::string& name, const retrieval::Measures& m) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %d |\n", name.c_str(), m.nn,
                  m.first_tier, m.second_tier, m.e_measure, m.dcg, m.queries);
    o << buf;
}


}  // namespace

int evaluate_command(const std::string& matrix, const std::string& labels_path, bool json, const std::string& pr_path) {
    const Eigen::MatrixXd D = read_matrix(matrix);
    const std::vector<std::string> labels = read_labels(labels_path);
    const retrieval::Evaluation e = retrieval::evaluate(D, labels);
    if (!pr_path.empty()) {
        std::ostringstream pr;
        pr << "recall,precision\n";
        for (size_t k = 0; k < e.recall.size(); ++k) pr << e.recall[k] << "," << e.precision[k] << "\n";
        io::write_file_atomic(pr_path, pr.str());
    }
    if (json) {
        std::cout << "{\"micro\": " << retrieval::to_json(e.micro) << ", \"macro\": " << retrieval::to_json(e.macro) << ", \"classes\": {";
        for (size_t k = 0; k < e.classes.size(); ++k)
            std::cout << (k ? ", " : "") << "\"" << e.classes[k] << "\": " << retrieval::to_json(e.per_class[k]);
        std::cout << "}, \"precision\": [";
        for (size_t k = 0; k < e.precision.size(); ++k) std::cout << (k ? ", " : "") << e.precision[k];
        std::cout << "]}\n";
        return 0;
    }
    std::cout << "| average | NN | 1-Tier | 2-Tier | E-measure | DCG | queries |\n|---|---|---|---|---|---|---|\n";
    print_row(std::cout, "micro", e.micro);
    print_row(std::cout, "macro", e.macro);
    std::cout << "\n| class | NN | 1-Tier | 2-Tier | E-measure | DCG | queries |\n|---|---|---|---|---|---|---|\n";
    for (size_t k = 0; k < e.classes.size(); ++k) print_row(std::cout, e.classes[k], e.per_class[k]);
    if (!e.skipped_classes.empty()) {
        std::cout << "\nleft out (two models or fewer):";
        for (const auto& c : e.skipped_classes) std::cout << " " << c;
        std::cout << "\n";
    }
    return 0;
}

}  // namespace canonform::cli
