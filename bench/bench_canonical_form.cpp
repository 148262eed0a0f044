// Benchmark of one canonical-form method on one mesh file:
//   canonform_bench_canonical MESH [--method euclidean|geodesic-ls|geodesic-classical|geodesic-fast]
//                             [--variant A|N] [--solver auto|direct|multigrid] [--repeats R] [--threads T]
// Prints one JSON line: vertices, median/min/max seconds of R runs, iterations, and memory
// (VmRSS after loading the mesh, peak VmHWM after the runs, both in MiB, from /proc/self/status).
// The Euclidean method is single-threaded; the geodesic ones use --threads (default 1).
// bench/run_bench.sh and bench/run_table1.sh run it over meshes of several sizes.
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/canonical/geodesic_canonical_form.h"
#include "canonform/numerics/sparse_cholesky.h"
#include "canonform/io/mesh_io.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <string>
#include <vector>

namespace {

double status_mib(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) return std::atof(line.c_str() + std::strlen(key)) / 1024.0;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: canonform_bench_canonical MESH [--variant A|N] [--solver auto|direct|multigrid] [--repeats R]\n");
        return 2;
    }
    canonform::EuclideanCanonicalFormOptions opt;
    canonform::GeodesicCanonicalFormOptions gopt;
    gopt.threads = 1;
    gopt.max_memory_gib = 20;
    gopt.max_seconds = 1e6;
    std::string method = "euclidean";
    std::string requested_solver = "auto";
    int repeats = 5;
    for (int k = 2; k + 1 < argc; k += 2) {
        if (!std::strcmp(argv[k], "--variant"))
            opt.variant = argv[k + 1][0] == 'A' ? canonform::CanonicalVariant::A : canonform::CanonicalVariant::N;
        else if (!std::strcmp(argv[k], "--repeats"))
            repeats = std::max(1, std::atoi(argv[k + 1]));
        else if (!std::strcmp(argv[k], "--threads"))
            gopt.threads = std::atoi(argv[k + 1]);
        else if (!std::strcmp(argv[k], "--method"))
            method = argv[k + 1];
        else if (!std::strcmp(argv[k], "--solver")) {
            const std::string v = argv[k + 1];
            requested_solver = v;
            opt.linear_solver = v == "direct"      ? canonform::LinearSolver::Direct
                                : v == "multigrid" ? canonform::LinearSolver::Multigrid
                                                   : canonform::LinearSolver::Auto;
        }
    }
    if (method == "geodesic-ls") gopt.method = canonform::GeodesicMds::LeastSquares;
    else if (method == "geodesic-classical") gopt.method = canonform::GeodesicMds::Classical;
    else if (method == "geodesic-fast") gopt.method = canonform::GeodesicMds::Fast;
    else if (method != "euclidean") {
        std::fprintf(stderr, "canonform_bench_canonical: unknown method %s\n", method.c_str());
        return 2;
    }
    const bool geodesic = method != "euclidean";
    const std::string label = geodesic ? method : std::string("euclidean-") + (opt.variant == canonform::CanonicalVariant::A ? "A" : "N");
    try {
        const auto m = canonform::io::read_mesh(argv[1]);
        const double rss_loaded = status_mib("VmRSS:");
        std::vector<double> t;
        int iterations = 0;
        size_t features = 0;
        std::string solver = canonform::SparseCholesky::backend();
        double geodesic_s = 0, estimate_s = 0, estimate_mib = 0;
        for (int k = 0; k < repeats; ++k) {
            if (geodesic) {
                const auto r = canonform::geodesic_canonical_form(m.V, m.F, gopt);
                t.push_back(r.seconds);
                iterations = r.iterations;
                geodesic_s = r.geodesic_seconds;
                estimate_s = r.estimate.seconds;
                estimate_mib = r.estimate.bytes / (1024.0 * 1024.0);
            } else {
                const auto r = canonform::euclidean_canonical_form(m.V, m.F, opt);
                t.push_back(r.seconds);
                iterations = r.iterations;
                features = r.features.size();
                if (r.linear_solver == canonform::LinearSolver::Multigrid) solver = "AMG V-cycle";
            }
        }
        std::sort(t.begin(), t.end());
        std::printf("{\"vertices\": %ld, \"method\": \"%s\", \"variant\": \"%c\", \"repeats\": %d, "
                    "\"median_s\": %.6f, \"min_s\": %.6f, \"max_s\": %.6f, \"iterations\": %d, "
                    "\"feature_points\": %zu, \"geodesic_s\": %.6f, \"estimated_s\": %.3f, \"estimated_mib\": %.1f, "
                    "\"rss_loaded_mib\": %.1f, \"peak_mib\": %.1f, \"solver\": \"%s\", \"requested_solver\": \"%s\", "
                    "\"threads\": %d}\n",
                    long(m.V.rows()), label.c_str(), opt.variant == canonform::CanonicalVariant::A ? 'A' : 'N',
                    repeats, t[t.size() / 2], t.front(), t.back(), iterations, features, geodesic_s, estimate_s,
                    estimate_mib, rss_loaded, status_mib("VmHWM:"), solver.c_str(), requested_solver.c_str(),
                    geodesic ? gopt.threads : 1);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "canonform_bench_canonical: %s\n", e.what());
        return 1;
    }
    return 0;
}
