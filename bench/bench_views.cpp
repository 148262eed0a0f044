// Benchmark of the view-based descriptor (issue targets: a ~10k-vertex mesh's descriptor - 66
// renders + SIFT + histograms - in at most 1 s on one core; a 600 x 600 clock-matching distance
// matrix in at most 60 s on 2 cores). Prints JSON lines with medians.
//   canonform_bench_views MESH [--repeats R]
#include "canonform/views/bag_of_features.h"
#include "canonform/views/codebook.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"
#include "bench_util.h"
#include "canonform/io/mesh_io.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

using canonform::bench::Clock;
using canonform::bench::median;
using canonform::bench::since;

int main(int argc, char** argv) {
    using namespace canonform::views;
    if (argc < 2) {
        std::fprintf(stderr, "usage: canonform_bench_views MESH [--repeats R]\n");
        return 2;
    }
    const int repeats = argc > 3 && !std::strcmp(argv[2], "--repeats") ? std::max(1, std::atoi(argv[3])) : 5;
    const auto m = canonform::io::read_mesh(argv[1]);

    // A codebook from this mesh's own features (the timing of the assignment is what matters).
    const ViewSet first = compute_views(m.V, m.F);
    SiftDescriptors all(0, 128);
    for (const auto& f : first.features) {
        SiftDescriptors g(all.rows() + f.rows(), 128);
        g << all, f;
        all = g;
    }
    CodebookOptions co;
    auto t0 = Clock::now();
    const Codebook cb = Codebook::train(all, co);
    const double train_s = since(t0);

    std::vector<double> views_s, total_s;
    for (int r = 0; r < repeats; ++r) {
        t0 = Clock::now();
        const ViewSet vs = compute_views(m.V, m.F);
        views_s.push_back(since(t0));
        const auto h = view_histograms(vs, cb);
        total_s.push_back(since(t0));
    }
    std::printf("{\"bench\": \"descriptor\", \"vertices\": %ld, \"repeats\": %d, \"median_s\": %.4f, "
                "\"views_and_sift_s\": %.4f, \"keypoints\": %ld, \"codebook_words\": %d, \"codebook_train_s\": %.3f}\n",
                long(m.V.rows()), repeats, median(total_s), median(views_s), long(all.rows()), cb.size(), train_s);

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
    t0 = Clock::now();
    const Eigen::MatrixXf D = distance_matrix(models, maps, 2);
    std::printf("{\"bench\": \"distance_matrix\", \"models\": %ld, \"threads\": 2, \"seconds\": %.2f}\n", long(D.rows()),
                since(t0));
    return 0;
}
