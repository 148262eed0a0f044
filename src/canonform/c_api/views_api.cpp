// SPDX-License-Identifier: GPL-3.0-or-later
// canonform C API (canonform.h): the view descriptor (CM-BOF) - views and SIFT, codebooks,
// histograms, clock-matching distances, descriptor files.
#include "canonform/c_api/c_api_support.h"
#include "canonform/c_api/json_text.h"

#ifdef CANONFORM_C_API_VIEWS
#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"
#endif
#ifdef CANONFORM_C_API_OPENCV
#include "canonform/views/opencv_sift.h"
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>

using namespace canonform;
using namespace canonform::c_api;

namespace {

#ifdef CANONFORM_C_API_OPENCV
// The `opencv` SIFT extractor lives in a library of its own (opencv_sift.h): registered when this
// library is loaded, where the build links it.
const bool g_opencv_registered = [] {
    views::register_opencv_sift();
    return true;
}();
#endif

#ifdef CANONFORM_C_API_VIEWS
using views::Codebook;
using views::DescriptorMatrix;
using views::Histogram;

/// n x 128 row-major floats as descriptors.
DescriptorMatrix descriptors_in(const float* X, std::int64_t n, const char* name) {
    if (n < 0) throw InputError(std::string(name) + ": a negative row count (" + std::to_string(n) + ")");
    if (n > 0 && !X) throw InputError(std::string(name) + " is NULL with " + std::to_string(n) + " rows");
    if (n == 0) return DescriptorMatrix(0, 128);
    return Eigen::Map<const DescriptorMatrix>(X, n, 128);
}

/// Dense histograms (views x words doubles) as sparse (word, count) rows; `which` names them.
std::vector<Histogram> histograms_in(const double* H, std::int64_t views, std::int64_t words,
                                     const std::string& which) {
    const Eigen::MatrixXd M = matrix_in(H, views, words, which.c_str());
    std::vector<Histogram> out(static_cast<size_t>(M.rows()));
    for (Eigen::Index v = 0; v < M.rows(); ++v)
        for (Eigen::Index w = 0; w < M.cols(); ++w) {
            const double x = M(v, w);
            if (!std::isfinite(x))
                throw InputError(which + " has a NaN or infinite count (view " + std::to_string(v) + ")");
            if (x != 0) out[static_cast<size_t>(v)].emplace_back(static_cast<int>(w), static_cast<float>(x));
        }
    return out;
}

/// Sparse histograms of one model as a dense FLOAT32 (views, words) array.
ArrayPtr histograms_out(const std::vector<Histogram>& h, int words) {
    ArrayPtr a(new_array(CANONFORM_FLOAT32, 2, static_cast<std::int64_t>(h.size()), words));
    float* d = a.data<float>();
    std::fill(d, d + h.size() * static_cast<size_t>(words), 0.0f);
    for (size_t v = 0; v < h.size(); ++v)
        for (const auto& [word, count] : h[v])
            d[v * static_cast<size_t>(words) + static_cast<size_t>(word)] = count;
    return a;
}

/// The views' SIFT descriptors stacked as FLOAT32 (n, 128).
ArrayPtr stacked_out(const std::vector<views::SiftDescriptors>& f) {
    std::int64_t n = 0;
    for (const auto& m : f) n += m.rows();
    ArrayPtr a(new_array(CANONFORM_FLOAT32, 2, n, 128));
    float* d = a.data<float>();
    for (const auto& m : f) {
        if (m.size()) std::memcpy(d, m.data(), sizeof(float) * static_cast<size_t>(m.size()));
        d += m.size();
    }
    return a;
}

ArrayPtr counts_out(const std::vector<int>& counts) {
    return indices_out(counts);
}

views::ViewDescriptorOptions view_options(const char* sift, std::int64_t image_size, std::int64_t seed) {
    check_range("image_size", image_size, 32, 2048);
    check_range("seed", seed, 0, 4294967295LL);
    views::ViewDescriptorOptions o;
    o.image_size = static_cast<int>(image_size);
    o.pose.seed = static_cast<std::uint64_t>(seed);
    if (sift) o.sift.backend = views::parse_sift_backend(sift);
    return o;
}
#endif

#ifndef CANONFORM_C_API_VIEWS
[[noreturn]] void no_views() {
    throw Unsupported("this build of canonform has no views area (configure with CANONFORM_VIEWS=ON)");
}
#endif

}  // namespace

extern "C" {

const char* canonform_sift_backends(void) {
#ifdef CANONFORM_C_API_VIEWS
    static const std::string names = [] {
        std::string s;
        for (const std::string& n : views::sift_backend_names()) s += (s.empty() ? "" : ",") + n;
        return s;
    }();
    return names.c_str();
#else
    return "";
#endif
}

int canonform_sift_backend_available(const char* name) {
#ifdef CANONFORM_C_API_VIEWS
    if (!name) return 0;
    for (const std::string& n : views::sift_backend_names())
        if (n == name) return views::sift_backend_available(views::parse_sift_backend(n)) ? 1 : 0;
#else
    (void)name;
#endif
    return 0;
}

const char* canonform_default_sift(void) {
#ifdef CANONFORM_C_API_VIEWS
    static const std::string name = views::sift_backend_name(views::SiftOptions{}.backend);
    return name.c_str();
#else
    return "";
#endif
}

const char* canonform_codebook_methods(void) {
#if !defined(CANONFORM_C_API_VIEWS)
    return "";
#elif defined(CANONFORM_C_API_WITHOUT_FAISS)
    return "lloyd,random";
#else
    return "kmeans,lloyd,random";
#endif
}

int canonform_view_descriptor(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                              const float* codebook_words, int64_t nwords, const char* codebook_path,
                              const char* sift, int64_t image_size, int64_t seed, canonform_array** features,
                              canonform_array** counts) {
    clear_outputs(features, counts);
    return guarded([&] {
        require_out(features, "features");
        require_out(counts, "counts");
#ifdef CANONFORM_C_API_VIEWS
        const views::ViewDescriptorOptions o = view_options(sift, image_size, seed);
        std::optional<Codebook> cb;
        if (codebook_path)
            cb = Codebook::load(codebook_path);
        else if (codebook_words)
            cb = Codebook::from_words(descriptors_in(codebook_words, nwords, "codebook"));
        const Eigen::MatrixXd v = vertices_in(V, nv);
        const Eigen::MatrixXi f = faces_in(F, nf);
        const views::ViewSet vs = views::compute_views(v, f, o);
        const views::ModelDescriptor d =
            views::make_descriptor(vs.features, cb ? &*cb : nullptr, "", o.image_size);
        ArrayPtr data = cb ? histograms_out(d.histograms, d.codebook_words) : stacked_out(d.raw);
        ArrayPtr n = counts_out(d.keypoints_per_view);
        *features = data.release();
        *counts = n.release();
#else
        (void)V, (void)nv, (void)F, (void)nf, (void)codebook_words, (void)nwords, (void)codebook_path,
            (void)sift, (void)image_size, (void)seed;
        no_views();
#endif
    });
}

int canonform_train_codebook(const float* descriptors, int64_t n, int64_t words, int64_t sample, int64_t seed,
                             const char* method, canonform_array** words_out) {
    clear_outputs(words_out);
    return guarded([&] {
        require_out(words_out, "words_out");
#ifdef CANONFORM_C_API_VIEWS
        check_range("words", words, 1, 1000000);
        check_range("sample", sample, 0, 2000000000LL);
        check_range("seed", seed, 0, 4294967295LL);
        views::CodebookOptions o;
        o.words = static_cast<int>(words);
        o.sample = sample;
        o.seed = static_cast<std::uint64_t>(seed);
        o.method = views::parse_codebook_method(method ? method : "kmeans");
        const Codebook cb = Codebook::train(descriptors_in(descriptors, n, "descriptors"), o);
        ArrayPtr a(new_array(CANONFORM_FLOAT32, 2, cb.size(), 128));
        if (cb.size())
            std::memcpy(a.p->data, cb.words().data(), sizeof(float) * static_cast<size_t>(cb.words().size()));
        *words_out = a.release();
#else
        (void)descriptors, (void)n, (void)words, (void)sample, (void)seed, (void)method;
        no_views();
#endif
    });
}

int canonform_save_codebook(const char* path, const float* words, int64_t nwords) {
    return guarded([&] {
#ifdef CANONFORM_C_API_VIEWS
        const std::string p = text_in(path, "path");
        Codebook::from_words(descriptors_in(words, nwords, "words")).save(p);
#else
        (void)path, (void)words, (void)nwords;
        no_views();
#endif
    });
}

int canonform_load_codebook(const char* path, canonform_array** words) {
    clear_outputs(words);
    return guarded([&] {
        require_out(words, "words");
#ifdef CANONFORM_C_API_VIEWS
        const Codebook cb = Codebook::load(text_in(path, "path"));
        ArrayPtr a(new_array(CANONFORM_FLOAT32, 2, cb.size(), 128));
        if (cb.size())
            std::memcpy(a.p->data, cb.words().data(), sizeof(float) * static_cast<size_t>(cb.words().size()));
        *words = a.release();
#else
        (void)path;
        no_views();
#endif
    });
}

int canonform_read_descriptor(const char* path, char** meta, canonform_array** data) {
    clear_outputs(meta, data);
    return guarded([&] {
        require_out(meta, "meta");
        require_out(data, "data");
#ifdef CANONFORM_C_API_VIEWS
        const views::ModelDescriptor d = views::read_descriptor(text_in(path, "path"));
        JsonWriter j;
        j.begin_object()
            .key("source")
            .value(d.source)
            .key("views")
            .value(d.views)
            .key("image_size")
            .value(d.image_size);
        j.key("codebook_words").value(d.codebook_words).key("keypoints_per_view").begin_array();
        for (int k : d.keypoints_per_view) j.value(k);
        j.end_array().end_object();
        ArrayPtr a =
            d.codebook_words > 0 ? histograms_out(d.histograms, d.codebook_words) : stacked_out(d.raw);
        *meta = text_out(j.text());
        *data = a.release();
#else
        (void)path;
        no_views();
#endif
    });
}

int canonform_clock_distance(const double* A, int64_t views_a, int64_t words_a, const double* B,
                             int64_t views_b, int64_t words_b, double* distance) {
    return guarded([&] {
        require_out(distance, "distance");
#ifdef CANONFORM_C_API_VIEWS
        const std::vector<Histogram> a = histograms_in(A, views_a, words_a, "A"),
                                     b = histograms_in(B, views_b, words_b, "B");
        *distance = views::clock_matching_distance(a, b, views::rotation_view_maps());
#else
        (void)A, (void)views_a, (void)words_a, (void)B, (void)views_b, (void)words_b;
        no_views();
#endif
    });
}

int canonform_distance_matrix(const double* const* histograms, const int64_t* views, const int64_t* words,
                              int64_t n, int threads, canonform_progress_fn progress, void* user, float* D) {
    return guarded([&] {
#ifdef CANONFORM_C_API_VIEWS
        check_range("threads", threads, 0, 1024);
        if (n < 0) throw InputError("a negative number of descriptors (" + std::to_string(n) + ")");
        if (n > 0 && (!histograms || !views || !words))
            throw InputError("descriptors: NULL arrays for " + std::to_string(n) + " models");
        if (n > 0) require_out(D, "D");
        std::vector<std::vector<Histogram>> models;
        for (int64_t k = 0; k < n; ++k) {
            const std::string which = "descriptor " + std::to_string(k);
            if (k > 0 && words[k] != words[0])
                throw InputError(which + " has " + std::to_string(words[k]) + " words, descriptor 0 " +
                                 std::to_string(words[0]) + ": histograms of one codebook are needed");
            models.push_back(histograms_in(histograms[k], views[k], words[k], which));
        }
        const ProgressFn report = progress_in(progress, user);
        // The upper triangle in row blocks of about equal work, progress (and cancelling) between
        // them; distance_rows() gives the floats distance_matrix() gives.
        const auto maps = views::rotation_view_maps();
        const auto size = static_cast<Eigen::Index>(n);
        Eigen::MatrixXf M = Eigen::MatrixXf::Zero(size, size);
        const auto count = static_cast<size_t>(n);
        const double pairs =
            0.5 * static_cast<double>(count) * static_cast<double>(count > 0 ? count - 1 : 0);
        const double per_block = std::max(1.0, pairs / 32);
        double done = 0;
        for (size_t begin = 0; begin < count;) {
            size_t end = begin;
            double work = 0;
            while (end < count && (work < per_block || end == begin))
                work += static_cast<double>(count - 1 - end++);
            const Eigen::MatrixXf rows = views::distance_rows(models, maps, begin, end, threads);
            M.middleRows(static_cast<Eigen::Index>(begin), rows.rows()) = rows;
            done += work;
            report_progress(report, pairs > 0 ? done / pairs : 1.0, "clock-matching distances");
            begin = end;
        }
        for (Eigen::Index r = 0; r < M.rows(); ++r)
            for (Eigen::Index c = r + 1; c < M.cols(); ++c) M(c, r) = M(r, c);
        if (n > 0)
            Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(D, size, size) =
                M;
#else
        (void)histograms, (void)views, (void)words, (void)n, (void)threads, (void)progress, (void)user,
            (void)D;
        no_views();
#endif
    });
}

}  // extern "C"
