// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmark of the view-based descriptor of one mesh, per SIFT backend, side by side in one run
// (issue targets: a 10k-vertex mesh's descriptor - pose + 66 renders + SIFT + histograms - in at
// most 0.15 CPU s; a 600 x 600 clock-matching distance matrix in at most 60 s on 2 cores). CPU
// seconds of the process (all threads; the machine may be shared), medians over the repeats,
// the backends interleaved. Prints JSON lines.
//   canonform_bench_views MESH [--repeats R] [--backends canonform,opencv] [--distances 0|1]
// (--distances 0: without the distance matrix)
// A backend may carry OpenCV options: NAME@CONTRAST[@LAYERS], e.g. opencv-half@0.0005@4.
#include "bench_util.h"
#include "canonform/common/heap_pages.h"
#include "canonform/io/mesh_io.h"
#include "canonform/views/bag_of_features.h"
#include "canonform/views/codebook.h"
#include "canonform/views/opencv_sift.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using canonform::bench::Clock;
using canonform::bench::median;
using canonform::bench::since;

namespace {
double cpu() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
}  // namespace

int main(int argc, char** argv) {
    canonform::advise_heap_huge_pages();  // as the tool does (common/heap_pages.h)
    canonform::views::register_opencv_sift();
    using namespace canonform::views;
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: canonform_bench_views MESH [--repeats R] [--backends canonform,opencv] "
                     "[--distances 0|1]\n");
        return 2;
    }
    int repeats = 5;
    bool distances = true;
    std::vector<std::string> backends = {"canonform", "opencv"};
    for (int k = 2; k + 1 < argc; k += 2) {
        if (!std::strcmp(argv[k], "--repeats")) repeats = std::max(1, std::atoi(argv[k + 1]));
        if (!std::strcmp(argv[k], "--distances")) distances = std::atoi(argv[k + 1]) != 0;
        if (!std::strcmp(argv[k], "--backends")) {
            backends.clear();
            std::stringstream ss(argv[k + 1]);
            for (std::string b; std::getline(ss, b, ',');) backends.push_back(b);
        }
    }
    const auto m = canonform::io::read_mesh(argv[1]);
    const auto sift_options = [](const std::string& spec) {  // NAME[@CONTRAST[@LAYERS]]
        SiftOptions o;
        std::stringstream ss(spec);
        std::string part;
        std::getline(ss, part, '@');
        o.backend = parse_sift_backend(part);
        if (std::getline(ss, part, '@')) o.contrast_threshold = std::stod(part);
        if (std::getline(ss, part, '@')) o.octave_layers = std::stoi(part);
        return o;
    };

    // Per backend: a codebook from this mesh's own features (the assignment's cost is what
    // matters; the whole descriptor (compute_views + histograms) and SIFT alone are timed below).
    // Trained before anything is timed, then a pause: OpenBLAS's worker threads (FAISS's k-means
    // runs on BLAS) spin-wait for a while after start-up and after each BLAS call, and that spin
    // is process CPU time. Timed right after start-up, the single-threaded pose normalisation
    // measured 0.020 or 0.035-0.045 CPU s depending on the process (its thread's CPU time was
    // 0.020 in every one; with OPENBLAS_NUM_THREADS=1 always 0.020).
    std::map<std::string, Codebook> cbs;
    std::map<std::string, std::vector<double>> total, sift;
    std::map<std::string, long> keypoints;
    for (const auto& b : backends) {
        ViewDescriptorOptions o;
        o.sift = sift_options(b);
        o.keep_images = false;
        const ViewSet vs = compute_views(m.V, m.F, o);
        std::vector<const std::vector<SiftDescriptors>*> sets = {&vs.features};
        const SiftDescriptors all = stack_features(sets);
        keypoints[b] = long(all.rows());
        cbs[b] = Codebook::train(all, {});
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));

    // Pose normalisation alone.
    std::vector<double> pose_cpu;
    for (int r = 0; r < repeats; ++r) {
        const double c0 = cpu();
        normalize_pose(m.V, m.F);
        pose_cpu.push_back(cpu() - c0);
    }
    std::vector<double> pose_exact_cpu;  // without the direction-binned coarse search
    PoseOptions exact;
    exact.direction_bins = 0;
    for (int r = 0; r < repeats; ++r) {
        const double c0 = cpu();
        normalize_pose(m.V, m.F, exact);
        pose_exact_cpu.push_back(cpu() - c0);
    }
    const PoseNormalization pose = normalize_pose(m.V, m.F);
    const Eigen::MatrixXd X = apply_pose(pose, m.V);
    // The 66 renders alone: one at a time, and as compute_views makes them (33 antipodal pairs, one
    // pass each), interleaved.
    std::vector<double> render_cpu, render_pairs_cpu;
    std::vector<DepthImage> images;
    for (int r = 0; r < repeats; ++r) {
        double c0 = cpu();
        for (const Eigen::Vector3d& d : view_directions()) render_depth(X, m.F, d, 256);
        render_cpu.push_back(cpu() - c0);
        c0 = cpu();
        images = render_views(X, m.F, 256);
        render_pairs_cpu.push_back(cpu() - c0);
    }
    std::printf(
        "{\"bench\": \"pose_and_renders\", \"vertices\": %ld, \"repeats\": %d, \"pose_cpu_s\": %.4f, "
        "\"pose_every_face_cpu_s\": %.4f, \"renders_cpu_s\": %.4f, \"renders_in_pairs_cpu_s\": %.4f}\n",
        long(m.V.rows()), repeats, median(pose_cpu), median(pose_exact_cpu), median(render_cpu),
        median(render_pairs_cpu));

    for (int r = 0; r < repeats; ++r)
        for (const auto& b : backends) {  // interleaved: the load hits every backend alike
            ViewDescriptorOptions o;
            o.sift = sift_options(b);
            o.keep_images = false;
            double c0 = cpu();
            const ViewSet vs = compute_views(m.V, m.F, o);
            const auto h = view_histograms(vs, cbs[b]);
            total[b].push_back(cpu() - c0);
            c0 = cpu();
            for (const auto& img : images) depth_sift_descriptors(img.depth, img.size, o.sift);
            sift[b].push_back(cpu() - c0);
        }
    for (const auto& b : backends) {  // keypoints per octave of the view (-1: opencv's doubled image)
        std::map<int, long> per_octave;
        for (const auto& img : images)
            for (const SiftKeypoint& k : depth_sift_features(img.depth, img.size, sift_options(b)).keypoints)
                ++per_octave[k.octave];
        std::printf("{\"bench\": \"keypoints_per_octave\", \"sift\": \"%s\"", b.c_str());
        for (const auto& [octave, n] : per_octave) std::printf(", \"%d\": %ld", octave, n);
        std::printf("}\n");
    }
    for (const auto& b : backends)
        std::printf(
            "{\"bench\": \"descriptor\", \"sift\": \"%s\", \"vertices\": %ld, \"repeats\": %d, "
            "\"median_cpu_s\": %.4f, \"sift_cpu_s\": %.4f, \"keypoints\": %ld, \"keypoints_per_view\": "
            "%.1f}\n",
            b.c_str(), long(m.V.rows()), repeats, median(total[b]), median(sift[b]), keypoints[b],
            double(keypoints[b]) / 66.0);
    std::fflush(stdout);
    if (!distances) return 0;

    // 600 x 600 distance matrix with the real 24 cube rotations, sparse random histograms of the
    // size real views have (30-100 of 1500 words), 2 threads.
    const auto maps = rotation_view_maps();
    std::mt19937_64 rng(42);
    std::vector<std::vector<Histogram>> models(600);
    for (auto& model : models) {
        for (int v = 0; v < 66; ++v) {
            std::vector<int> words;
            const int n = 30 + static_cast<int>(rng() % 71);
            for (int k = 0; k < n; ++k) words.push_back(static_cast<int>(rng() % 1500));
            model.push_back(histogram(words));
        }
    }
    const auto t0 = Clock::now();
    const Eigen::MatrixXf D = distance_matrix(models, maps, 2);
    std::printf("{\"bench\": \"distance_matrix\", \"models\": %ld, \"threads\": 2, \"seconds\": %.2f}\n",
                long(D.rows()), since(t0));
    return 0;
}
