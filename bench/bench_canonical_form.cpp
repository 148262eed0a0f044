// Benchmark of the Euclidean canonical form on one mesh file:
//   canonform_bench_canonical MESH [--variant A|N] [--repeats R]
// Prints one JSON line: vertices, median/min/max seconds of R runs, SMACOF iterations, and memory
// (VmRSS after loading the mesh, peak VmHWM after the runs, both in MiB, from /proc/self/status).
// Single-threaded. bench/run_bench.sh runs it over meshes of several sizes and writes the tables.
#include "core/euclidean_canonical_form.h"
#include "core/sparse_cholesky.h"
#include "mesh_io.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
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
        std::fprintf(stderr, "usage: canonform_bench_canonical MESH [--variant A|N] [--repeats R]\n");
        return 2;
    }
    canonform::EuclideanCanonicalFormOptions opt;
    int repeats = 5;
    for (int k = 2; k + 1 < argc; k += 2) {
        if (!std::strcmp(argv[k], "--variant"))
            opt.variant = argv[k + 1][0] == 'A' ? canonform::CanonicalVariant::A : canonform::CanonicalVariant::N;
        else if (!std::strcmp(argv[k], "--repeats"))
            repeats = std::max(1, std::atoi(argv[k + 1]));
    }
    try {
        const auto m = canonform::io::read_mesh(argv[1]);
        const double rss_loaded = status_mib("VmRSS:");
        std::vector<double> t;
        canonform::EuclideanCanonicalFormResult r;
        for (int k = 0; k < repeats; ++k) {
            r = canonform::euclidean_canonical_form(m.V, m.F, opt);
            t.push_back(r.seconds);
        }
        std::sort(t.begin(), t.end());
        std::printf("{\"vertices\": %ld, \"variant\": \"%c\", \"repeats\": %d, \"median_s\": %.6f, \"min_s\": %.6f, "
                    "\"max_s\": %.6f, \"iterations\": %d, \"feature_points\": %zu, \"rss_loaded_mib\": %.1f, "
                    "\"peak_mib\": %.1f, \"solver\": \"%s\"}\n",
                    long(m.V.rows()), opt.variant == canonform::CanonicalVariant::A ? 'A' : 'N', repeats,
                    t[t.size() / 2], t.front(), t.back(), r.iterations, r.features.size(), rss_loaded,
                    status_mib("VmHWM:"), canonform::SparseCholesky::backend());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "canonform_bench_canonical: %s\n", e.what());
        return 1;
    }
    return 0;
}
