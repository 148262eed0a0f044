// canonform tool: `canonform retrieve` - a retrieval experiment over a labelled collection.
#pragma once

#include <string>
#include <vector>

namespace canonform::cli {

/// What `canonform retrieve` runs.
struct RetrieveOptions {
    std::string dataset;               ///< folder the label paths are relative to
    std::string labels;                ///< CSV "path,class" (header optional)
    std::string out;                   ///< run folder
    std::vector<std::string> methods;  ///< none, euclidean-A, euclidean-N, geodesic-ls, -classical, -fast
    int words = 1500;                  ///< codebook size (trained on each method's forms)
    std::string codebook;              ///< a given codebook instead ("" = train)
    int simplify = 0;                  ///< simplify every mesh to this many vertices first (0 = no)
    double noise = 0;                  ///< vertex noise, as a fraction of the mean edge length
    unsigned long long seed = 0;       ///< seeds of the noise and the codebook
    int threads = 0;                   ///< 0 = all cores
};

/// Runs every method: per mesh (in parallel, cached by file content and parameters) the canonical
/// form and the SIFT features of its 66 views; then the codebook, the descriptors, the distance
/// matrix (binary float32 and CSV) and the measures. Writes RUN/METHOD/{forms,descriptors}/,
/// distances.bin(.csv), metrics.json, pr.csv, failures.txt and RUN/report.md.
int retrieve_command(const RetrieveOptions& o);

}  // namespace canonform::cli
