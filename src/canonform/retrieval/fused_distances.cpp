// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/fused_distances.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>

namespace canonform::retrieval {

namespace {

std::string number(double w) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", w);
    return buf;
}

bool equal_weights(const FusedSpec& s) {
    return s.default_weights;
}

const char* kMedianPrefix = "fused-median:";

}  // namespace

bool is_fused_spec(const std::string& text) {
    return text.rfind("fused:", 0) == 0 || text.rfind(kMedianPrefix, 0) == 0;
}

std::string FusedSpec::to_string() const {
    const bool plain = equal_weights(*this);
    std::string s = rule == FusionRule::GlobalMedian ? kMedianPrefix : "fused:";
    for (size_t k = 0; k < members.size(); ++k)
        s += (k ? "+" : "") + members[k] + (plain ? "" : "*" + number(weights[k]));
    return s;
}

std::string FusedSpec::folder(const std::vector<std::string>& member_folders) const {
    const bool plain = equal_weights(*this);
    std::string s = rule == FusionRule::GlobalMedian ? "fused-median_" : "fused_";
    for (size_t k = 0; k < member_folders.size(); ++k)
        s += (k ? "+" : "") + member_folders[k] + (plain || k >= weights.size() ? "" : number(weights[k]));
    return s;
}

FusedSpec parse_fused_spec(const std::string& text) {
    if (!is_fused_spec(text))
        throw InputError("'" + text + "' is not a fused method (fused:A+B... or fused-median:A+B...)");
    FusedSpec s;
    s.rule = text.rfind(kMedianPrefix, 0) == 0 ? FusionRule::GlobalMedian : FusionRule::RowZScore;
    const std::string body = text.substr(text.find(':') + 1);
    int weighted = 0;
    size_t start = 0;
    while (true) {
        const size_t plus = body.find('+', start);
        const std::string part =
            body.substr(start, plus == std::string::npos ? std::string::npos : plus - start);
        const size_t star = part.find('*');
        const std::string member = part.substr(0, star);
        if (member.empty()) throw InputError("'" + text + "': a member of the fused method is empty");
        double w = 1;
        if (star != std::string::npos) {
            const std::string ws = part.substr(star + 1);
            char* end = nullptr;
            w = std::strtod(ws.c_str(), &end);
            if (ws.empty() || *end != '\0' || !std::isfinite(w) || !(w > 0))
                throw InputError("'" + text + "': the weight '" + ws + "' of " + member +
                                 " is not a number > 0");
            ++weighted;
        }
        s.members.push_back(member);
        s.weights.push_back(w);
        if (plus == std::string::npos) break;
        start = plus + 1;
    }
    if (s.members.size() < 2)
        throw InputError("'" + text + "': a fused method needs two or more members (fused:A+B)");
    if (std::set<std::string>(s.members.begin(), s.members.end()).size() != s.members.size())
        throw InputError("'" + text + "': a member is named twice");
    if (weighted != 0 && weighted != static_cast<int>(s.members.size()))
        throw InputError("'" + text + "': give a weight to every member or to none");
    if (weighted == 0) {
        s.default_weights = true;
        const bool has_none = std::find(s.members.begin(), s.members.end(), "none") != s.members.end();
        const double none_weight =
            s.rule == FusionRule::GlobalMedian ? kFusedMedianNoneWeight : kFusedNoneWeight;
        const double others = static_cast<double>(s.members.size()) - (has_none ? 1.0 : 0.0);
        for (size_t k = 0; k < s.members.size(); ++k)
            s.weights[k] = !has_none                ? 1.0 / others
                           : s.members[k] == "none" ? none_weight
                                                    : (1.0 - none_weight) / others;
    }
    return s;
}

double off_diagonal_median(const Eigen::MatrixXf& D) {
    if (D.rows() != D.cols() || D.rows() < 2)
        throw InputError("fused distances: a member's distance matrix is not square of two models or more");
    std::vector<float> v;
    v.reserve(static_cast<size_t>(D.rows() * (D.rows() - 1)));
    for (Eigen::Index i = 0; i < D.rows(); ++i)
        for (Eigen::Index j = 0; j < D.cols(); ++j)
            if (i != j) v.push_back(D(i, j));
    const size_t h = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h), v.end());
    double m = v[h];
    if (v.size() % 2 == 0) {
        const float below = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h));
        m = 0.5 * (static_cast<double>(below) + m);
    }
    return m;
}

Eigen::MatrixXd row_zscores(const Eigen::MatrixXf& D) {
    if (D.rows() != D.cols() || D.rows() < 3)
        throw InputError("fused distances: a member's distance matrix is not square of three models or more");
    const Eigen::Index n = D.rows();
    Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
        double sum = 0, sq = 0;
        for (Eigen::Index j = 0; j < n; ++j)
            if (j != i) sum += D(i, j);
        const double mean = sum / static_cast<double>(n - 1);
        for (Eigen::Index j = 0; j < n; ++j)
            if (j != i) sq += (D(i, j) - mean) * (D(i, j) - mean);
        const double sd = std::sqrt(sq / static_cast<double>(n - 1));
        const double scale = sd > 0 ? 1.0 / sd : 1.0;
        for (Eigen::Index j = 0; j < n; ++j)
            if (j != i) Z(i, j) = (D(i, j) - mean) * scale;
    }
    return Z;
}

Eigen::MatrixXf fuse_distances(const std::vector<Eigen::MatrixXf>& D, const std::vector<double>& weights,
                               FusionRule rule) {
    if (D.empty()) throw InputError("fused distances: no member matrix");
    if (D.size() != weights.size())
        throw InputError("fused distances: one weight per member matrix is needed");
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(D[0].rows(), D[0].cols());
    for (size_t k = 0; k < D.size(); ++k) {
        if (D[k].rows() != D[0].rows() || D[k].cols() != D[0].cols())
            throw InputError("fused distances: the member matrices differ in size");
        if (!std::isfinite(weights[k])) throw InputError("fused distances: a weight is not finite");
        if (rule == FusionRule::RowZScore) {
            sum += weights[k] * row_zscores(D[k]);
        } else {
            const double m = off_diagonal_median(D[k]);
            sum += (weights[k] / (m > 0 ? m : 1.0)) * D[k].cast<double>();
        }
    }
    if (rule == FusionRule::GlobalMedian) return sum.cast<float>();
    const Eigen::Index n = sum.rows();
    Eigen::MatrixXd F = 0.5 * (sum + sum.transpose());
    double lowest = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j)
            if (i != j) lowest = std::min(lowest, F(i, j));
    F.array() -= lowest;
    F.diagonal().setZero();
    return F.cast<float>();
}

}  // namespace canonform::retrieval
