// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: visual-word codebook (vector quantisation of SIFT descriptors) for bag-of-features.
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape retrieval
// using Clock Matching and Bag-of-Features", Machine Vision and Applications 24, 2013 (Sec. 3.3:
// a codebook of N_W = 1500 words, each view a histogram of nearest-word counts); J. Sivic and
// A. Zisserman, "Video Google", ICCV 2003; D. Arthur and S. Vassilvitskii, "k-means++: the
// advantages of careful seeding", SODA 2007.
//
// Training (every method draws from its own std::mt19937_64 stream seeded by `seed`; no global RNG):
// - The training set is a seeded random sample of `sample` distinct descriptors (all of them if
//   there are fewer, or if sample == 0). Chosen by measurement (docs/design.md, "Retrieval defaults"): on
//   TOSCA, k-means on a 100k sample scores within noise of the previous codebook (Lloyd on every descriptor);
//   on the 600 x 10k plan's 1.2 M descriptors it costs a twelfth.
// - Method::KMeans (default): FAISS's k-means (faiss::Clustering with an exact L2 index; Debian's
//   libfaiss-dev): words initialised as distinct random sample points (FAISS's own seeded choice,
//   not k-means++), kmeans_iterations Lloyd iterations whose nearest-word search is a BLAS sgemm,
//   an empty cluster re-seeded by splitting a large one. The search is FAISS's exact one with the
//   passes around its products done in one (codebook_training.cpp): the same words as with
//   FAISS's own index. Deterministic for a seed and a thread count. The BLAS it uses is whatever
//   libblas.so.3 resolves to: with Debian's reference BLAS it is several times slower than with
//   OpenBLAS (libopenblas0-pthread, installed by tools/setup.sh; docs/benchmarks.md).
// - Method::Lloyd: our own Lloyd's k-means, seeded by k-means++ (on a seeded subset of at most
//   20 * words sample descriptors: k-means++ is sequential, one pass per word); results do not
//   depend on the thread count. An empty cluster is re-seeded with the descriptor farthest from
//   its current word. Stops after kmeans_iterations or when no assignment changes. Kept as the
//   reference FAISS was measured against (same measures, slower: docs/design.md).
// - Method::Random: `words` distinct descriptors drawn uniformly (the public re-implementation
//   that Pickup et al. used picks random training descriptors).
// - Fewer training descriptors than words is refused (InputError with both numbers): the codebook
//   never has fewer words than asked for. With exactly as many, every descriptor becomes a word
//   (in input order).
//
// Assignment: nearest word in squared Euclidean distance, ties to the lower word index, the same
// on every CPU. SIFT descriptors are integers 0-255 (both extractors write them so); for those, and
// words in [0, 511] (a codebook of SIFT descriptors: means of such values), the distance is taken to
// the words rounded to 1/64 (a change below 1/128 per value, about a thousandth of the distance
// between a descriptor and its word), in 16-bit integers with exact integer sums: no rounding, so
// the choice is the same whatever instructions compute it: 8 lanes with AVX2, 4 with SSE2, and on
// CPUs with AVX-512 VNNI sixteen words at a time, each pair of values multiplied and added in one
// instruction (chosen at run time; codebook.cpp).
// Other descriptors or words: exact squared distances in double, summed in a fixed order. One
// thread: a view's descriptors take well under a millisecond (bench/bench_views.cpp).
// The training code (train, train_on_rows, training_rows) is in its own library,
// canonform::codebook_training (codebook_training.cpp), which brings FAISS, BLAS and OpenMP; reading
// codebooks and assigning words needs none of them.
//
// File format (little endian, written atomically: temp file + rename):
//   bytes 0-3   magic "CFCB"
//   bytes 4-7   uint32 version (= 1)
//   bytes 8-11  uint32 number of words W (> 0)
//   bytes 12-15 uint32 dimension D (= 128)
//   then W * D float32, word-major (word 0's 128 values first); all finite. Nothing after.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace canonform::views {

/// Values per SIFT descriptor (Lowe Sec. 6.1: 4 x 4 cells x 8 orientations).
constexpr int kDescriptorSize = 128;
/// n x 128 descriptors, one per row.
using DescriptorMatrix = Eigen::Matrix<float, Eigen::Dynamic, kDescriptorSize, Eigen::RowMajor>;

/// Default training sample (descriptors); chosen by measurement (docs/design.md, "Retrieval defaults").
inline constexpr std::int64_t kDefaultCodebookSample = 100000;

/// Options of Codebook::train().
struct CodebookOptions {
    int words = 1500;        ///< codebook size N_W (> 0)
    std::uint64_t seed = 0;  ///< seed of the random stream (sample, initial words, random choice)
    enum class Method { KMeans, Lloyd, Random };
    /// The default method: KMeans (FAISS) in a build with FAISS; Lloyd (ours) in one without it
    /// (CMake's CANONFORM_WITHOUT_FAISS, which every user of the views library sees: the Windows
    /// build), where KMeans is refused.
#ifdef CANONFORM_WITHOUT_FAISS
    static constexpr Method kDefaultMethod = Method::Lloyd;
#else
    static constexpr Method kDefaultMethod = Method::KMeans;
#endif
    Method method = kDefaultMethod;
    int kmeans_iterations = 10;  ///< Lloyd iterations after seeding (>= 0)
    /// Training descriptors drawn (seeded, distinct) from the input before training; 0 = all.
    std::int64_t sample = kDefaultCodebookSample;
};

/// The method named "kmeans", "lloyd" or "random" (InputError naming the choices otherwise).
CodebookOptions::Method parse_codebook_method(const std::string& name);
/// The name of a method ("kmeans", "lloyd", "random").
std::string codebook_method_name(CodebookOptions::Method method);

class Codebook;
namespace detail {
std::vector<int> assign_with(const Codebook& codebook, const DescriptorMatrix& descriptors,
                             const std::string& path);
}  // namespace detail

/// A set of visual words (size() x 128).
class Codebook {
public:
    Codebook() = default;

    /// Trains a codebook from training descriptors (rows). Throws InputError if there are no
    /// descriptors, a value is not finite, or an option is out of range.
    static Codebook train(const DescriptorMatrix& descriptors, const CodebookOptions& options = {});

    /// The rows of `total` stacked descriptors that train() trains on, in the order it uses them:
    /// the seeded sample (drawn order), or every row 0..total-1 when no sample is drawn.
    static std::vector<int> training_rows(std::int64_t total, const CodebookOptions& options = {});

    /// train() for a caller that holds only the rows training_rows(total, options) names, in that
    /// order (e.g. read mesh by mesh from a cache): the same codebook as train() on all `total`.
    static Codebook train_on_rows(const DescriptorMatrix& rows, std::int64_t total,
                                  const CodebookOptions& options = {});

    /// Wraps given words (rows); throws InputError if empty or not finite.
    static Codebook from_words(DescriptorMatrix words);

    /// Number of words.
    int size() const { return static_cast<int>(words_.rows()); }

    /// Index in [0, size()) of the nearest word of every descriptor (row), as described above.
    /// Throws InputError on an empty codebook.
    std::vector<int> assign(const DescriptorMatrix& descriptors) const;

    /// Writes the binary file described above (atomic). Throws if it cannot be written.
    void save(const std::string& path) const;

    /// Reads a file written by save(). Throws InputError naming the problem (missing, a folder,
    /// unreadable, wrong magic, unsupported version, bad dimension, truncated, trailing bytes,
    /// non-finite values).
    static Codebook load(const std::string& path);
    /// Parses the bytes of a codebook file (as load()); `where` starts every message.
    static Codebook parse(const std::string& bytes, const std::string& where);

    /// The words, size() x 128.
    const DescriptorMatrix& words() const { return words_; }

private:
    friend std::vector<int> detail::assign_with(const Codebook&, const DescriptorMatrix&, const std::string&);
    std::vector<int> assign_by(const DescriptorMatrix& descriptors, int search) const;
    int nearest_exact(const float* x) const;

    DescriptorMatrix words_;
    bool quantised_ = false;             // every word in [0, 511]: qwords_ and qnorms_ are set
    std::vector<std::int16_t> qwords_;   // round(64 word), word-major
    std::vector<std::int64_t> qnorms_;   // |qword|^2
    std::vector<std::int16_t> qblocks_;  // qwords_ in blocks of 16 words, transposed (codebook.cpp)
};

namespace detail {
/// The word searches of assign() this CPU can run ("portable", and "avx512-vnni" where the CPU has
/// AVX-512 VNNI; assign() takes the last). They give the same words: tests compare them.
std::vector<std::string> word_search_paths();
/// assign() with the named word search (InputError if unknown or not runnable here).
std::vector<int> assign_with(const Codebook& codebook, const DescriptorMatrix& descriptors,
                             const std::string& path);
}  // namespace detail

}  // namespace canonform::views
