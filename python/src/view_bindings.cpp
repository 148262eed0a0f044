// SPDX-License-Identifier: GPL-3.0-or-later
// canonform Python module: the view-based descriptor (CM-BOF) - views and SIFT, codebooks,
// histograms, clock-matching distances, descriptor files.
#include "bindings.h"
#include "support.h"

#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace canonform::python {

namespace {

using views::Codebook;
using views::Histogram;
using views::SiftDescriptors;

bool is_path(const py::handle& o) {
    return py::isinstance<py::str>(o) || py::isinstance<py::bytes>(o) ||
           py::isinstance(o, py::module_::import("os").attr("PathLike"));
}

/// A codebook given as its words (W, 128) or as a codebook file.
Codebook codebook_in(const py::handle& c) {
    if (is_path(c)) {
        const std::string p = path_in(c);
        Call call;
        return call.run([&] { return Codebook::load(p); });
    }
    if (c.is_none()) throw InputError("codebook is None");
    return Codebook::from_words(descriptors_in(c, "codebook"));
}

/// Dense histograms (views, words) as rows of (word, count); `which` names them in messages.
std::vector<Histogram> histograms_in(const py::handle& h, const std::string& which) {
    const Eigen::MatrixXd H = matrix_in(h, which.c_str());
    std::vector<Histogram> out(static_cast<size_t>(H.rows()));
    for (Eigen::Index v = 0; v < H.rows(); ++v)
        for (Eigen::Index w = 0; w < H.cols(); ++w) {
            const double x = H(v, w);
            if (!std::isfinite(x)) throw InputError(which + " has a NaN or infinite count (view " + std::to_string(v) + ")");
            if (x != 0) out[static_cast<size_t>(v)].emplace_back(static_cast<int>(w), static_cast<float>(x));
        }
    return out;
}

/// Sparse histograms of one model as a dense float32 (views, words) array.
py::array_t<float> histograms_out(const std::vector<Histogram>& h, int words) {
    py::array_t<float> a({static_cast<py::ssize_t>(h.size()), static_cast<py::ssize_t>(words)});
    std::fill(a.mutable_data(), a.mutable_data() + a.size(), 0.0f);
    auto r = a.mutable_unchecked<2>();
    for (size_t v = 0; v < h.size(); ++v)
        for (const auto& [word, count] : h[v]) r(static_cast<py::ssize_t>(v), word) = count;
    return a;
}

py::list features_out(const std::vector<SiftDescriptors>& f) {
    py::list out;
    for (const auto& m : f) out.append(array_out(m));
    return out;
}

/// Appends every (n, 128) array of a nested sequence, in order (a model's list of views, a list of models).
void collect_features(const py::handle& o, std::vector<SiftDescriptors>* out, int depth) {
    if (py::isinstance<py::array>(o) && py::array::ensure(o).ndim() == 2) {
        out->push_back(descriptors_in(o, "features"));
        return;
    }
    if (depth < 3 && (py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o))) {
        for (const py::handle& x : o) collect_features(x, out, depth + 1);
        return;
    }
    out->push_back(descriptors_in(o, "features"));  // anything else array-like, or its error
}

views::ViewDescriptorOptions view_options(const std::optional<std::string>& sift, int image_size, long long seed) {
    if (image_size < 32 || image_size > 2048)
        throw InputError("image_size must be between 32 and 2048, got " + std::to_string(image_size));
    if (seed < 0 || seed > 4294967295LL) throw InputError("seed must be between 0 and 4294967295, got " + std::to_string(seed));
    views::ViewDescriptorOptions o;
    o.image_size = image_size;
    o.pose.seed = static_cast<std::uint64_t>(seed);
    if (sift) o.sift.backend = views::parse_sift_backend(*sift);
    return o;
}

py::object view_descriptor(const py::object& V, const py::object& F, const py::object& codebook,
                           const std::optional<std::string>& sift, int image_size, long long seed) {
    const views::ViewDescriptorOptions o = view_options(sift, image_size, seed);
    std::optional<Codebook> cb;
    if (!codebook.is_none()) cb = codebook_in(codebook);
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F);
    Call call;
    const views::ModelDescriptor d = call.run([&] {
        const views::ViewSet vs = views::compute_views(v, f, o);
        return views::make_descriptor(vs.features, cb ? &*cb : nullptr, "", o.image_size);
    });
    if (cb) return histograms_out(d.histograms, d.codebook_words);
    return features_out(d.raw);
}

py::array_t<float> train_codebook(const py::object& features, int words, long long sample, long long seed,
                                  const std::string& method) {
    if (words < 1 || words > 1000000) throw InputError("words must be between 1 and 1000000, got " + std::to_string(words));
    if (sample < 0 || sample > 2000000000LL)
        throw InputError("sample must be between 0 and 2000000000, got " + std::to_string(sample));
    if (seed < 0 || seed > 4294967295LL) throw InputError("seed must be between 0 and 4294967295, got " + std::to_string(seed));
    views::CodebookOptions o;
    o.words = words;
    o.sample = sample;
    o.seed = static_cast<std::uint64_t>(seed);
    o.method = views::parse_codebook_method(method);
    std::vector<SiftDescriptors> parts;
    collect_features(features, &parts, 0);
    Call call;
    const Codebook cb = call.run([&] {
        const std::vector<const std::vector<SiftDescriptors>*> sets{&parts};
        return Codebook::train(views::stack_features(sets), o);
    });
    return array_out(cb.words());
}

void save_codebook(const py::object& path, const py::object& words) {
    const std::string p = path_in(path);
    const Codebook cb = Codebook::from_words(descriptors_in(words, "words"));
    Call call;
    call.run([&] { cb.save(p); });
}

py::array_t<float> load_codebook(const py::object& path) {
    const std::string p = path_in(path);
    Call call;
    return array_out(call.run([&] { return Codebook::load(p); }).words());
}

py::dict read_descriptor(const py::object& path) {
    const std::string p = path_in(path);
    Call call;
    const views::ModelDescriptor d = call.run([&] { return views::read_descriptor(p); });
    py::dict out;
    out["source"] = text(d.source);
    out["views"] = d.views;
    out["image_size"] = d.image_size;
    out["codebook_words"] = d.codebook_words;
    out["keypoints_per_view"] = d.keypoints_per_view;
    if (d.codebook_words > 0)
        out["histograms"] = histograms_out(d.histograms, d.codebook_words);
    else
        out["features"] = features_out(d.raw);
    return out;
}

double clock_distance(const py::object& A, const py::object& B) {
    const std::vector<Histogram> a = histograms_in(A, "A"), b = histograms_in(B, "B");
    Call call;
    return call.run([&] { return views::clock_matching_distance(a, b, views::rotation_view_maps()); });
}

py::array_t<float> distance_matrix(const py::iterable& descriptors, int threads, const py::object& progress) {
    if (threads < 0 || threads > 1024) throw InputError("threads must be between 0 and 1024, got " + std::to_string(threads));
    std::vector<std::vector<Histogram>> models;
    py::ssize_t words = -1;
    for (const py::handle& d : descriptors) {
        const std::string which = "descriptor " + std::to_string(models.size());
        const py::array a = py::array::ensure(d);
        if (a && a.ndim() == 2) {
            if (words >= 0 && a.shape(1) != words)
                throw InputError(which + " has " + std::to_string(a.shape(1)) + " words, descriptor 0 " +
                                 std::to_string(words) + ": histograms of one codebook are needed");
            words = a.shape(1);
        }
        models.push_back(histograms_in(d, which));
    }
    const size_t n = models.size();
    // The upper triangle in row blocks of about equal work, Ctrl-C and progress between them;
    // distance_rows() gives the floats distance_matrix() gives.
    Call call(progress);
    const auto maps = views::rotation_view_maps();
    Eigen::MatrixXf D = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    call.run([&] {
        const double pairs = 0.5 * static_cast<double>(n) * static_cast<double>(n > 0 ? n - 1 : 0);
        const double per_block = std::max(1.0, pairs / 32);
        double done = 0;
        for (size_t begin = 0; begin < n;) {
            size_t end = begin;
            double work = 0;
            while (end < n && (work < per_block || end == begin)) work += static_cast<double>(n - 1 - end++);
            const Eigen::MatrixXf rows = views::distance_rows(models, maps, begin, end, threads);
            D.middleRows(static_cast<Eigen::Index>(begin), rows.rows()) = rows;
            done += work;
            call.check(pairs > 0 ? done / pairs : 1.0, "clock-matching distances");
            begin = end;
        }
        for (Eigen::Index r = 0; r < D.rows(); ++r)
            for (Eigen::Index c = r + 1; c < D.cols(); ++c) D(c, r) = D(r, c);
    });
    return array_out(D);
}

}  // namespace

void bind_views(py::module_& m) {
    m.def("sift_backends", &views::sift_backend_names,
          "The names of the SIFT extractors view_descriptor() and retrieve() take as sift=...");
    m.def("default_sift", [] { return views::sift_backend_name(views::SiftOptions{}.backend); },
          "The SIFT extractor used when sift=None (the library's default, as the tool's).");
    m.def("view_descriptor", &view_descriptor, py::arg("V"), py::arg("F"), py::arg("codebook") = py::none(),
          py::kw_only(), py::arg("sift") = py::none(), py::arg("image_size") = 256, py::arg("seed") = 0,
          R"(The CM-BOF view descriptor of a mesh (`canonform descriptor`): pose normalisation,
66 depth views of image_size pixels, SIFT per view.

V: float32/float64 (#V, 3); F: integer (#F, 3) (several components allowed).
codebook: None, a (W, 128) float array of visual words (train_codebook()) or a
codebook file. With a codebook, returns float32 (66, W): one bag-of-features
histogram per view (word counts); without, the raw features: a list of 66
float32 (n_i, 128) arrays (n_i keypoints of view i). sift: None (default_sift())
or one of sift_backends(); seed: the pose's rectilinearity restarts.)");
    m.def("train_codebook", &train_codebook, py::arg("features"), py::arg("words") = 1500,
          py::arg("sample") = views::kDefaultCodebookSample, py::arg("seed") = 0, py::kw_only(),
          py::arg("method") = "kmeans", R"(Trains a codebook of visual words (`canonform codebook`).

features: a float (n, 128) array, or a list of them (view_descriptor()'s raw
features), or a list of such lists (several models), stacked in order. sample:
descriptors drawn (seeded) to train on, 0 = all; method: "kmeans" (FAISS),
"lloyd" or "random". Returns float32 (words, 128); fewer descriptors than words
raises InputError with both numbers.)");
    m.def("save_codebook", &save_codebook, py::arg("path"), py::arg("words"),
          "Writes words (W, 128) as a codebook file (the tool's format; atomic).");
    m.def("load_codebook", &load_codebook, py::arg("path"), "Reads a codebook file: float32 (W, 128) words.");
    m.def("read_descriptor", &read_descriptor, py::arg("path"), R"(Reads a descriptor file (.cfvd, `canonform descriptor`): a dict with source,
views, image_size, codebook_words, keypoints_per_view and either histograms
(float32 (views, codebook_words)) or features (a list of float32 (n_i, 128)).)");
    m.def("clock_distance", &clock_distance, py::arg("A"), py::arg("B"),
          R"(The clock-matching distance of two descriptors: A, B (66, W) histograms
(view_descriptor() with one codebook). The minimum over the 24 rotations of the
cube of the summed view distances; 0 for equal descriptors.)");
    m.def("distance_matrix", &distance_matrix, py::arg("descriptors"), py::kw_only(), py::arg("threads") = 0,
          py::arg("progress") = py::none(),
          R"(The N x N clock-matching distance matrix of a list of N (66, W) histograms
(`canonform distance`): float32 (N, N), symmetric, zero diagonal. threads: 0 =
every core; progress and Ctrl-C as canonical_form().)");
}

}  // namespace canonform::python
