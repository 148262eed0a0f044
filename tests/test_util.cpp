// SPDX-License-Identifier: GPL-3.0-or-later
#include "test_util.h"

#include "canonform/numerics/rigid_alignment.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace canonform::test {

double aligned_rms(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    const numerics::RigidAlignment al = numerics::align_rigid(a, b);
    const double radius =
        std::sqrt((b.rowwise() - b.colwise().mean()).squaredNorm() / static_cast<double>(b.rows()));
    return al.rms / radius;
}

double aligned_rms_or_mirrored(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    Eigen::MatrixXd m = a;
    m.col(0) *= -1;
    return std::min(aligned_rms(a, b), aligned_rms(m, b));
}

std::string scratch_dir(const std::string& name) {
    namespace fs = std::filesystem;
    const fs::path p = fs::temp_directory_path() / ("canonform_test_" + name);
    fs::remove_all(p);
    fs::create_directories(p);
    return p.string();
}

std::string message_of(const std::function<void()>& fn) {
    try {
        fn();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

void fuzz_seed(const std::string& target, const std::string& name, const std::string& bytes) {
    const char* root = std::getenv("CANONFORM_FUZZ_SEEDS");
    if (!root || !*root) return;
    const std::filesystem::path dir = std::filesystem::path(root) / target;
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name, std::ios::binary) << bytes;
}

}  // namespace canonform::test
