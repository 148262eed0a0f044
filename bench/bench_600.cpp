// SPDX-License-Identifier: GPL-3.0-or-later
// Per-stage costs of a 600-model retrieval run (issue 5's plan: 600 meshes of 10k vertices in at
// most 15 minutes on 2 cores). On a few real 10k-vertex meshes it measures, one mesh at a time on
// one thread: the Euclidean canonical form (variant N and A) and the 66 depth views + SIFT. It
// then builds a 600-model descriptor pool by repeating those meshes' real SIFT descriptors and
// measures the codebook (k-means++ seeding and one Lloyd iteration over all descriptors, and the
// alternative of training on a random sample of them), the assignment of every descriptor to
// its word (the histograms) and the 600 x 600 clock-matching distance matrix of the repeated
// real histograms on 2 threads. Every stage reports wall seconds and CPU seconds (all threads):
// the machine may be shared, and CPU seconds are what an extrapolation to 2 idle cores needs.
// Prints one JSON line per stage.
//   canonform_bench_600 MESH... [--models 600] [--words 1500] [--sample 100000] [--threads 2] [--all]
//       [--sift canonform|opencv]
// (--all: also FAISS k-means on every descriptor, no sample)
#include "bench_util.h"
#include "canonform/canonical/euclidean_canonical_form.h"
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
#include <random>
#include <string>
#include <vector>

namespace {

using canonform::bench::Clock;
using canonform::bench::median;

/// The BLAS library this process has loaded (from /proc/self/maps), e.g. openblas-pthread/libblas.so.3.
std::string loaded_blas() {
    std::FILE* f = std::fopen("/proc/self/maps", "r");
    if (!f) return "?";
    char line[4096];
    std::string found;
    while (std::fgets(line, sizeof line, f)) {
        const std::string l = line;
        const auto p = l.find('/');
        if (p == std::string::npos) continue;
        const std::string path = l.substr(p, l.find_last_not_of("\n") + 1 - p);
        if ((path.find("blas") != std::string::npos) && found.find(path) == std::string::npos)
            found += (found.empty() ? "" : " ") + path;
    }
    std::fclose(f);
    return found.empty() ? "none" : found;
}

/// Wall and process CPU seconds of a stage.
struct Stopwatch {
    Clock::time_point w0 = Clock::now();
    double c0 = cpu();
    static double cpu() {
        timespec ts{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
        return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
    }
    double wall() const { return std::chrono::duration<double>(Clock::now() - w0).count(); }
    double cpu_s() const { return cpu() - c0; }
};

}  // namespace

int main(int argc, char** argv) {
    canonform::advise_heap_huge_pages();  // as the tool does (common/heap_pages.h)
    canonform::views::register_opencv_sift();
    using namespace canonform;
    using namespace canonform::views;
    std::vector<std::string> meshes;
    int models = 600, words = 1500, threads = 2;
    long sample = long(kDefaultCodebookSample);
    bool all_too = false;
    ViewDescriptorOptions view_options;
    view_options.keep_images = false;
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        if (a == "--all") {
            all_too = true;
        } else if (a == "--sift" && k + 1 < argc) {
            view_options.sift.backend = parse_sift_backend(argv[++k]);
        } else if (a.rfind("--", 0) == 0 && k + 1 < argc) {
            const long v = std::atol(argv[++k]);
            if (a == "--models")
                models = int(v);
            else if (a == "--words")
                words = int(v);
            else if (a == "--sample")
                sample = v;
            else if (a == "--threads")
                threads = int(v);
            else {
                std::fprintf(stderr, "unknown option %s\n", a.c_str());
                return 2;
            }
        } else {
            meshes.push_back(a);
        }
    }
    if (meshes.empty() || models < 2 || words < 1 || sample < words || threads < 1) {
        std::fprintf(stderr,
                     "usage: canonform_bench_600 MESH... [--models 600] [--words 1500] [--sample 100000] "
                     "[--threads 2] [--all]\n");
        return 2;
    }
    std::vector<double> n_wall, n_cpu, a_wall, a_cpu, v_wall, v_cpu, kp;
    std::vector<ViewSet> sets;
    long vertices = 0;
    for (const auto& path : meshes) {
        const auto m = io::read_mesh(path);
        vertices += m.V.rows();
        canonical::EuclideanCanonicalFormOptions o;
        Stopwatch s;
        const auto r = canonical::euclidean_canonical_form(m.V, m.F, o);
        n_wall.push_back(s.wall());
        n_cpu.push_back(s.cpu_s());
        o.variant = canonical::CanonicalVariant::A;
        s = Stopwatch();
        canonical::euclidean_canonical_form(m.V, m.F, o);
        a_wall.push_back(s.wall());
        a_cpu.push_back(s.cpu_s());
        s = Stopwatch();
        sets.push_back(compute_views(r.V, m.F, view_options));
        v_wall.push_back(s.wall());
        v_cpu.push_back(s.cpu_s());
        long n = 0;
        for (const auto& f : sets.back().features) n += f.rows();
        kp.push_back(double(n));
    }
    std::printf(
        "{\"stage\": \"canonical_form_N\", \"meshes\": %zu, \"mean_vertices\": %ld, \"median_wall_s\": %.3f, "
        "\"median_cpu_s\": %.3f}\n",
        meshes.size(), vertices / long(meshes.size()), median(n_wall), median(n_cpu));
    std::printf("{\"stage\": \"canonical_form_A\", \"median_wall_s\": %.3f, \"median_cpu_s\": %.3f}\n",
                median(a_wall), median(a_cpu));
    std::printf(
        "{\"stage\": \"views_and_sift\", \"sift\": \"%s\", \"median_wall_s\": %.3f, \"median_cpu_s\": %.3f, "
        "\"median_keypoints\": %.0f}\n",
        sift_backend_name(view_options.sift.backend).c_str(), median(v_wall), median(v_cpu), median(kp));
    std::fflush(stdout);

    // The 600-model descriptor pool: the real descriptors, repeated.
    std::vector<const SiftDescriptors*> per_model;
    long rows = 0;
    for (int k = 0; k < models; ++k) {
        const ViewSet& vs = sets[size_t(k) % sets.size()];
        for (const auto& f : vs.features) rows += f.rows();
    }
    SiftDescriptors all(rows, 128);
    long r = 0;
    for (int k = 0; k < models; ++k)
        for (const auto& f : sets[size_t(k) % sets.size()].features) {
            all.middleRows(r, f.rows()) = f;
            r += f.rows();
        }
    // The codebook by every method on the same seeded sample (10 iterations, the default), and
    // FAISS k-means on every descriptor for the cost of not sampling.
    Codebook cb;
    for (const char* method : {"kmeans", "lloyd", "random", "kmeans-all"}) {
        CodebookOptions co;
        co.words = words;
        co.sample = std::string(method) == "kmeans-all" ? 0 : sample;
        co.method = parse_codebook_method(std::string(method) == "kmeans-all" ? "kmeans" : method);
        if (std::string(method) == "kmeans-all" && !all_too) continue;
        Stopwatch s;
        Codebook c = Codebook::train(all, co);
        std::printf(
            "{\"stage\": \"codebook\", \"method\": \"%s\", \"descriptors\": %ld, \"sample\": %ld, "
            "\"words\": %d, \"iterations\": %d, \"wall_s\": %.2f, \"cpu_s\": %.2f, \"blas\": \"%s\"}\n",
            method, rows, long(co.sample), words, co.kmeans_iterations, s.wall(), s.cpu_s(),
            loaded_blas().c_str());
        std::fflush(stdout);
        if (std::string(method) == "kmeans") cb = c;
    }

    // Histograms: every descriptor of the 600 models assigned to its word.
    Stopwatch s;
    std::vector<std::vector<Histogram>> hist(sets.size());
    for (size_t k = 0; k < sets.size(); ++k)
        for (const auto& f : sets[k].features) hist[k].push_back(histogram(cb.assign(f)));
    const double per_pass_wall = s.wall(), per_pass_cpu = s.cpu_s();
    const double reps = double(models) / double(sets.size());
    std::printf(
        "{\"stage\": \"histograms\", \"models\": %d, \"wall_s\": %.2f, \"cpu_s\": %.2f, "
        "\"measured_on_models\": %zu}\n",
        models, per_pass_wall * reps, per_pass_cpu * reps, sets.size());
    std::fflush(stdout);

    std::vector<std::vector<Histogram>> hm(static_cast<size_t>(models));
    for (int k = 0; k < models; ++k) hm[size_t(k)] = hist[size_t(k) % hist.size()];
    s = Stopwatch();
    const Eigen::MatrixXf D = distance_matrix(hm, rotation_view_maps(), threads);
    std::printf(
        "{\"stage\": \"distance_matrix\", \"models\": %ld, \"threads\": %d, \"wall_s\": %.2f, \"cpu_s\": "
        "%.2f}\n",
        long(D.rows()), threads, s.wall(), s.cpu_s());
    return 0;
}
