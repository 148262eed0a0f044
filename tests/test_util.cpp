// SPDX-License-Identifier: GPL-3.0-or-later
#include "test_util.h"

#include "canonform/numerics/rigid_alignment.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <vector>

#include <unistd.h>

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

namespace {

// Paths removed, with everything under them, when the program ends; so are the paths beside them
// whose names extend theirs after a "_" (a test's NAME_PID_labels.csv next to its NAME_PID).
struct RemovedAtExit {
    std::mutex mutex;
    std::vector<std::filesystem::path> paths;
    ~RemovedAtExit() {
        namespace fs = std::filesystem;
        std::error_code ignored;
        for (const auto& p : paths) {
            fs::remove_all(p, ignored);
            const std::string prefix = p.filename().string() + "_";
            std::vector<fs::path> beside;
            for (fs::directory_iterator it(p.parent_path(), ignored), end; !ignored && it != end;
                 it.increment(ignored))
                if (it->path().filename().string().rfind(prefix, 0) == 0) beside.push_back(it->path());
            for (const auto& b : beside) fs::remove_all(b, ignored);
            ignored.clear();
        }
    }
};

RemovedAtExit& removed_at_exit() {
    static RemovedAtExit r;
    return r;
}

}  // namespace

std::string process_temp_path(const std::string& name) {
    const std::filesystem::path p =
        std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    RemovedAtExit& r = removed_at_exit();
    const std::lock_guard<std::mutex> lock(r.mutex);
    if (std::find(r.paths.begin(), r.paths.end(), p) == r.paths.end()) r.paths.push_back(p);
    return p.string();
}

std::string scratch_dir(const std::string& name) {
    const std::string p = process_temp_path("canonform_test_" + name);
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p;
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
