// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/view_descriptor.h"

#include "canonform/surface/mesh_topology.h"
#include "canonform/views/view_directions.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace canonform::views {

std::vector<int> ViewSet::keypoint_counts() const {
    std::vector<int> n;
    for (const auto& f : features) n.push_back(static_cast<int>(f.rows()));
    return n;
}

std::vector<DepthImage> render_views(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, int size) {
    const std::vector<Eigen::Vector3d> dirs = view_directions();
    const std::vector<int> opposite = opposite_views();
    std::vector<DepthImage> images(dirs.size());
    for (size_t i = 0; i < dirs.size(); ++i) {
        const size_t j = static_cast<size_t>(opposite[i]);
        if (j < i) continue;
        auto pair = render_depth_pair(X, F, dirs[i], size);
        images[i] = std::move(pair[0]);
        images[j] = std::move(pair[1]);
    }
    return images;
}

ViewSet compute_views(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                      const ViewDescriptorOptions& options) {
    surface::ValidationOptions vo;
    vo.min_vertices = 4;
    vo.require_single_component = false;  // a view of several parts is still a view
    surface::validate_mesh(V, F, vo);
    ViewSet s;
    s.pose = normalize_pose(V, F, options.pose);
    const Eigen::MatrixXd X = apply_pose(s.pose, V);
    // Each antipodal pair rendered in one pass (render_views' images) into buffers kept per thread,
    // and described before the next pair: no 66 images held unless asked for.
    const std::vector<Eigen::Vector3d> dirs = view_directions();
    const std::vector<int> opposite = opposite_views();
    const int size = options.image_size;
    const size_t pixels = static_cast<size_t>(size) * static_cast<size_t>(size);
    thread_local std::vector<float> front, back;
    front.resize(pixels);
    back.resize(pixels);
    s.features.resize(dirs.size());
    if (options.keep_images) s.images.resize(dirs.size());
    const DepthRenderer renderer(X, F, size);
    for (size_t i = 0; i < dirs.size(); ++i) {
        const size_t j = static_cast<size_t>(opposite[i]);
        if (j < i) continue;
        renderer.pair_into(dirs[i], front.data(), back.data());
        s.features[i] = depth_sift_descriptors(front.data(), size, options.sift);
        s.features[j] = depth_sift_descriptors(back.data(), size, options.sift);
        if (options.keep_images) {
            s.images[i] = {size, std::vector<float>(front.begin(), front.end())};
            s.images[j] = {size, std::vector<float>(back.begin(), back.end())};
        }
    }
    return s;
}

std::vector<Histogram> view_histograms(const std::vector<SiftDescriptors>& features,
                                       const Codebook& codebook) {
    std::vector<Histogram> h;
    for (const auto& f : features) h.push_back(histogram(codebook.assign(f)));
    return h;
}

ModelDescriptor make_descriptor(const std::vector<SiftDescriptors>& features, const Codebook* codebook,
                                const std::string& source, int image_size) {
    ModelDescriptor d;
    d.source = source;
    d.views = static_cast<int>(features.size());
    d.image_size = image_size;
    for (const auto& f : features) d.keypoints_per_view.push_back(static_cast<int>(f.rows()));
    if (codebook) {
        d.codebook_words = codebook->size();
        d.histograms = view_histograms(features, *codebook);
    } else {
        d.raw = features;
    }
    return d;
}

std::size_t feature_rows(const std::vector<SiftDescriptors>& views) {
    std::size_t n = 0;
    for (const auto& v : views) n += static_cast<std::size_t>(v.rows());
    return n;
}

SiftDescriptors stack_features(const std::vector<const std::vector<SiftDescriptors>*>& models) {
    std::size_t rows = 0;
    for (const auto* m : models) rows += feature_rows(*m);
    SiftDescriptors all(static_cast<Eigen::Index>(rows), 128);
    Eigen::Index r = 0;
    for (const auto* m : models)
        for (const auto& f : *m) {
            all.middleRows(r, f.rows()) = f;
            r += f.rows();
        }
    return all;
}

SiftDescriptors stacked_rows(
    const std::vector<std::size_t>& counts, const std::vector<int>& rows,
    const std::function<const std::vector<SiftDescriptors>&(std::size_t)>& features) {
    std::vector<std::pair<std::int64_t, Eigen::Index>> wanted;  // (row of the stack, place in the result)
    wanted.reserve(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) wanted.emplace_back(rows[i], static_cast<Eigen::Index>(i));
    std::sort(wanted.begin(), wanted.end());
    std::int64_t total = 0;
    for (std::size_t c : counts) total += static_cast<std::int64_t>(c);
    if (!wanted.empty() && (wanted.front().first < 0 || wanted.back().first >= total))
        throw InputError(
            "Codebook sample: row " +
            std::to_string(wanted.front().first < 0 ? wanted.front().first : wanted.back().first) +
            " is outside the " + std::to_string(total) + " stacked descriptors.");
    SiftDescriptors out(static_cast<Eigen::Index>(rows.size()), 128);
    std::size_t next = 0;
    std::int64_t base = 0;
    for (std::size_t g = 0; g < counts.size() && next < wanted.size(); ++g) {
        const std::int64_t end = base + static_cast<std::int64_t>(counts[g]);
        if (wanted[next].first < end) {
            const std::vector<SiftDescriptors>& held = features(g);
            const std::size_t n = feature_rows(held);
            if (n != counts[g])
                throw InputError("Codebook sample: model " + std::to_string(g) + " has " + std::to_string(n) +
                                 " descriptors, " + std::to_string(counts[g]) + " expected.");
            std::int64_t at = base;
            for (const SiftDescriptors& v : held)
                for (Eigen::Index r = 0; r < v.rows(); ++r, ++at)
                    while (next < wanted.size() && wanted[next].first == at)
                        out.row(wanted[next++].second) = v.row(r);
        }
        base = end;
    }
    return out;
}

}  // namespace canonform::views
