// SPDX-License-Identifier: GPL-3.0-or-later
#include "view_actions.h"

#include "canonform/meshlab/vcg_bridge.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_parameters.h"

#include "canonform/meshlab/meshlab_document.h"

#include <QImage>
#include <filesystem>

#include <algorithm>
#include <map>
#include <numeric>
#include <sstream>

namespace canonform::meshlab {

namespace {

/// The descriptor as one vector: with a codebook the V dense histograms (V x W word counts, view
/// 0 first); without, the raw SIFT descriptors (sum of keypoints_per_view rows x 128, view 0's
/// first), as in the descriptor file (descriptor_file.h).
std::vector<double> flatten(const views::ModelDescriptor& d) {
    std::vector<double> v;
    if (d.codebook_words > 0) {
        const size_t w = static_cast<size_t>(d.codebook_words);
        v.assign(d.histograms.size() * w, 0.0);
        for (size_t k = 0; k < d.histograms.size(); ++k)
            for (const auto& [word, count] : d.histograms[k]) v[k * w + static_cast<size_t>(word)] = count;
    } else {
        for (const auto& m : d.raw)
            for (Eigen::Index r = 0; r < m.rows(); ++r)
                for (Eigen::Index c = 0; c < m.cols(); ++c) v.push_back(m(r, c));
    }
    return v;
}

ActionOutputs depth_view_descriptor(const FilterSpec&, MeshDocument& md, const ParamValues& p,
                                    const ActionContext& ctx) {
    if (md.mm() == nullptr) throw InputError("there is no current mesh");
    MeshModel& mm = *md.mm();
    const std::string out = p.get_string("output_file");  // empty: no file (pymeshlab gets the vector)
    const std::string cb_path = p.get_string("codebook_file");
    // image_size, seed, sift: the library's definitions (views/view_parameters.h), checked.
    const ParameterSet<views::ViewDescriptorOptions> parameters =
        views::view_descriptor_parameters({}, views::builtin_sift_backend_names());
    views::ViewDescriptorOptions opt = parameters.read(p.texts(parameters.parameters()));
    opt.keep_images = !p.get_string("views_folder").empty();  // the images only when they are written
    const int size = opt.image_size;
    const views::Codebook* codebook = nullptr;
    views::Codebook cb;
    if (!cb_path.empty()) {
        cb = views::Codebook::load(cb_path);
        codebook = &cb;
    }
    report_progress(ctx.progress, 0.05, "pose normalisation and 66 depth views");
    const auto b = to_eigen(mm.cm);
    const views::ViewSet vs = views::compute_views(b.V, b.F, opt);
    report_progress(ctx.progress, 0.8, "writing the descriptor");

    const views::ModelDescriptor d =
        views::make_descriptor(vs.features, codebook, mm.fullName().toStdString(), size);
    const std::string views_dir = p.get_string("views_folder");
    if (!views_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(views_dir, ec);
        if (!std::filesystem::is_directory(views_dir))
            throw InputError("cannot create the folder '" + views_dir + "'");
        for (size_t k = 0; k < vs.images.size(); ++k) {
            const auto g = vs.images[k].gray();
            QImage img(g.data(), size, size, size, QImage::Format_Grayscale8);
            const QString f =
                QString("%1/view_%2.png").arg(QString::fromStdString(views_dir)).arg(k, 2, 10, QChar('0'));
            if (!img.save(f, "PNG")) throw InputError("cannot write '" + f.toStdString() + "'");
        }
    }
    if (!out.empty()) views::write_descriptor(out, d);

    const auto& n = d.keypoints_per_view;
    const int total = std::accumulate(n.begin(), n.end(), 0);
    std::ostringstream log;
    log << "Depth view descriptor of '" << mm.label().toStdString() << "': " << n.size() << " views of "
        << size << " px, SIFT keypoints per view min " << *std::min_element(n.begin(), n.end()) << ", mean "
        << total / static_cast<double>(n.size()) << ", max " << *std::max_element(n.begin(), n.end()) << " ("
        << total << " in all); "
        << (codebook ? "histograms over " + std::to_string(codebook->size()) + " words"
                     : std::string("raw SIFT features"))
        << "; pose by " << (vs.pose.used_rectilinearity ? "rectilinearity" : "PCA") << "; "
        << (out.empty() ? std::string("no file written (output_file empty)") : "written to " + out);
    ctx.log(log.str());
    return {{"views", int(n.size())},
            {"keypoints", total},
            {"codebook_words", d.codebook_words},
            {"keypoints_per_view", std::vector<double>(n.begin(), n.end())},
            {"descriptor", flatten(d)}};
}

using Action = ActionOutputs (*)(const FilterSpec&, MeshDocument&, const ParamValues&, const ActionContext&);

/// The action of every filter of the table, by Python name. A new filter: its table row
/// (view_filter_table.cpp), its action above and one line here.
const std::map<std::string, Action>& actions() {
    static const std::map<std::string, Action> a = {
        {"compute_depth_view_descriptor", depth_view_descriptor},
    };
    return a;
}

}  // namespace

ActionOutputs apply_view_action(int id, MeshDocument& md, const ParamValues& params,
                                const ActionContext& context) {
    const FilterSpec& spec = filter_spec(view_filter_table(), id);
    const auto it = actions().find(spec.python_name);
    if (it == actions().end()) throw InputError("filter '" + spec.name + "' has no action");
    return it->second(spec, md, params, context);
}

}  // namespace canonform::meshlab
