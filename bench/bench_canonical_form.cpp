// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmark of one canonical-form method on one mesh file:
//   canonform_bench_canonical MESH [--method euclidean|NAME[:KEY=VALUE...]] (any method of the registry)
//                             [--variant A|N] [--solver auto|direct|multigrid] [--repeats R] [--threads T]
//                             [--io OUT.ply]
// Prints one JSON line: vertices, median/min/max seconds of R runs, iterations, and memory
// (VmRSS after loading the mesh, peak VmHWM after the runs, both in MiB, from /proc/self/status).
// The Euclidean method is single-threaded; the geodesic ones use --threads (default 1).
// Without --io the mesh is read once, before the runs, and each run times the method alone; with
// --io each run also reads MESH and writes the form to OUT.ply (io::write_mesh, as the tool's
// `canonical` command does): the whole chain from file to file.
// bench/run_bench.sh and bench/run_table1.sh run it over meshes of several sizes.
#include "canonform/canonical/method_registry.h"
#include "canonform/common/heap_pages.h"
#include "canonform/io/mesh_io.h"
#include "canonform/numerics/sparse_cholesky.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

namespace {

double status_mib(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) return std::atof(line.c_str() + std::strlen(key)) / 1024.0;
    return 0;
}

/// A number of the run's summary (0 if the method does not report it).
double summary_number(const canonform::canonical::CanonicalForm& r, const std::string& key) {
    for (const auto& [k, v] : r.summary) {
        if (k != key) continue;
        if (const double* d = std::get_if<double>(&v)) return *d;
        if (const int* i = std::get_if<int>(&v)) return *i;
    }
    return 0;
}

std::string summary_text(const canonform::canonical::CanonicalForm& r, const std::string& key) {
    for (const auto& [k, v] : r.summary)
        if (k == key)
            if (const std::string* s = std::get_if<std::string>(&v)) return *s;
    return "";
}

}  // namespace

int main(int argc, char** argv) {
    canonform::advise_heap_huge_pages();  // as the tool does (common/heap_pages.h)
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: canonform_bench_canonical MESH [--method NAME[:KEY=VALUE...]] [--variant A|N] "
                     "[--solver auto|direct|multigrid] [--repeats R] [--threads T] [--io OUT.ply]\n");
        return 2;
    }
    std::string method = "euclidean", variant = "N", requested_solver = "auto", io_out;
    int repeats = 5, threads = 1;
    for (int k = 2; k + 1 < argc; k += 2) {
        if (!std::strcmp(argv[k], "--variant"))
            variant = argv[k + 1];
        else if (!std::strcmp(argv[k], "--repeats"))
            repeats = std::max(1, std::atoi(argv[k + 1]));
        else if (!std::strcmp(argv[k], "--threads"))
            threads = std::atoi(argv[k + 1]);
        else if (!std::strcmp(argv[k], "--method"))
            method = argv[k + 1];
        else if (!std::strcmp(argv[k], "--solver"))
            requested_solver = argv[k + 1];
        else if (!std::strcmp(argv[k], "--io"))
            io_out = argv[k + 1];
    }
    try {
        // "euclidean" + --variant is the registry's euclidean-A or euclidean-N; --solver sets the
        // Euclidean methods' solver; the geodesic ones get limits no bench mesh reaches.
        canonform::canonical::MethodSpec spec =
            canonform::canonical::parse_method_spec(method == "euclidean" ? "euclidean-" + variant : method);
        const canonform::canonical::CanonicalMethod& m = spec.method();
        if (m.parameter("solver")) spec.given.emplace_back("solver", requested_solver);
        if (m.parameter("max_memory_gib")) spec.given.emplace_back("max_memory_gib", "20");
        if (m.parameter("max_seconds")) spec.given.emplace_back("max_seconds", "1e6");
        const canonform::canonical::MethodSettings settings = spec.settings();
        canonform::canonical::MethodContext context;
        context.threads = threads;
        const auto mesh = canonform::io::read_mesh(argv[1]);
        const double rss_loaded = status_mib("VmRSS:");
        std::vector<double> t;
        canonform::canonical::CanonicalForm r;
        for (int k = 0; k < repeats; ++k) {  // wall time of the whole run, whatever the method
            const auto t0 = std::chrono::steady_clock::now();
            if (io_out.empty()) {
                r = m.run(mesh.V, mesh.F, settings, context);
            } else {
                const auto read = canonform::io::read_mesh(argv[1]);
                r = m.run(read.V, read.F, settings, context);
                canonform::io::write_mesh(io_out, r.V, read.F, r.quality);
            }
            t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        const std::string used = summary_text(r, "solver");
        const std::string solver =
            used == "multigrid" ? "AMG V-cycle" : canonform::numerics::SparseCholesky::backend();
        std::sort(t.begin(), t.end());
        std::printf(
            "{\"vertices\": %ld, \"method\": \"%s\", \"variant\": \"%c\", \"repeats\": %d, "
            "\"median_s\": %.6f, \"min_s\": %.6f, \"max_s\": %.6f, \"iterations\": %d, "
            "\"feature_points\": %zu, \"geodesic_s\": %.6f, \"estimated_s\": %.3f, \"estimated_mib\": %.1f, "
            "\"rss_loaded_mib\": %.1f, \"peak_mib\": %.1f, \"solver\": \"%s\", \"requested_solver\": \"%s\", "
            "\"threads\": %d, \"io\": %s}\n",
            long(mesh.V.rows()), m.name.c_str(), m.name == "euclidean-A" ? 'A' : 'N', repeats,
            t[t.size() / 2], t.front(), t.back(), int(summary_number(r, "iterations")), r.features.size(),
            summary_number(r, "geodesic_seconds"), summary_number(r, "estimated_seconds"),
            summary_number(r, "estimated_bytes") / (1024.0 * 1024.0), rss_loaded, status_mib("VmHWM:"),
            solver.c_str(), requested_solver.c_str(),
            m.family == canonform::canonical::MethodFamily::Geodesic ? threads : 1,
            io_out.empty() ? "false" : "true");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "canonform_bench_canonical: %s\n", e.what());
        return 1;
    }
    return 0;
}
