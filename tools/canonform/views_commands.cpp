#include "views_commands.h"

#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"
#include "canonform/io/mesh_io.h"
#include "qt_image.h"

#include <QImage>
#include <QPainter>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <numeric>
#include <sstream>
#include <sys/stat.h>

namespace canonform::cli {

namespace {

views::ViewDescriptorOptions view_options(const ViewCommandOptions& o) {
    if (o.image_size < 32 || o.image_size > 2048) throw InputError("--size must be between 32 and 2048 pixels");
    views::ViewDescriptorOptions v;
    v.image_size = o.image_size;
    v.pose.seed = o.seed;
    return v;
}

views::ViewSet views_of(const std::string& path, const ViewCommandOptions& o) {
    const io::MeshData m = io::read_mesh(path);
    try {
        return views::compute_views(m.V, m.F, view_options(o));
    } catch (const InputError& e) {
        throw InputError("'" + path + "': " + e.what());
    }
}

QImage to_qimage(const views::DepthImage& d) {
    const auto g = d.gray();
    return QImage(g.data(), d.size, d.size, d.size, QImage::Format_Grayscale8).copy();
}

}  // namespace

void write_distance_matrix(const Eigen::MatrixXf& D, const std::string& bin_path, const std::string& csv_path) {
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> R = D;
    io::write_file_atomic(bin_path, std::string(reinterpret_cast<const char*>(R.data()), sizeof(float) * R.size()));
    std::ostringstream csv;
    csv.precision(7);
    for (Eigen::Index i = 0; i < D.rows(); ++i)
        for (Eigen::Index j = 0; j < D.cols(); ++j) csv << D(i, j) << (j + 1 < D.cols() ? "," : "\n");
    io::write_file_atomic(csv_path, csv.str());
}

int views_command(const std::string& in, const std::string& dir, const ViewCommandOptions& o) {
    const views::ViewSet vs = views_of(in, o);
    mkdir(dir.c_str(), 0755);
    struct stat st {};
    if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw std::runtime_error("cannot create the folder '" + dir + "'");
    ensure_gui_application();  // fonts for the contact sheet's labels
    const int cols = 11, thumb = 128, label = 16;
    QImage sheet(cols * thumb, 6 * (thumb + label), QImage::Format_RGB888);
    sheet.fill(Qt::white);
    QPainter p(&sheet);
    QFont font = p.font();
    font.setPixelSize(11);
    p.setFont(font);
    const auto counts = vs.keypoint_counts();
    for (size_t k = 0; k < vs.images.size(); ++k) {
        const QImage img = to_qimage(vs.images[k]);
        char name[32];
        std::snprintf(name, sizeof name, "/view_%02zu.png", k);
        save_png(img, dir + name);
        const int x = static_cast<int>(k % cols) * thumb, y = static_cast<int>(k / cols) * (thumb + label);
        p.drawImage(QRect(x, y + label, thumb, thumb), img);
        p.drawText(QRect(x, y, thumb, label), Qt::AlignCenter, QString("view %1: %2 keypoints").arg(k).arg(counts[k]));
    }
    p.end();
    save_png(sheet, dir + "/contact_sheet.png");
    const int total = std::accumulate(counts.begin(), counts.end(), 0);
    std::cerr << "66 views of " << o.image_size << " px in " << dir << " (pose by "
              << (vs.pose.used_rectilinearity ? "rectilinearity" : "PCA") << ", " << total << " SIFT keypoints)\n";
    return 0;
}

int codebook_command(const std::string& out, const std::vector<std::string>& meshes, const ViewCommandOptions& o) {
    if (meshes.empty()) throw InputError("codebook needs at least one mesh");
    std::vector<views::SiftDescriptors> all;
    Eigen::Index rows = 0;
    for (size_t k = 0; k < meshes.size(); ++k) {
        const views::ViewSet vs = views_of(meshes[k], o);
        for (const auto& f : vs.features) {
            all.push_back(f);
            rows += f.rows();
        }
        std::cerr << "\r" << k + 1 << "/" << meshes.size() << " meshes, " << rows << " SIFT descriptors" << std::flush;
    }
    std::cerr << "\n";
    views::SiftDescriptors stacked(rows, 128);
    Eigen::Index r = 0;
    for (const auto& f : all) {
        stacked.middleRows(r, f.rows()) = f;
        r += f.rows();
    }
    views::CodebookOptions co;
    co.words = o.words;
    co.seed = o.seed;
    co.method = o.random_codebook ? views::CodebookOptions::Method::Random : views::CodebookOptions::Method::KMeans;
    const views::Codebook cb = views::Codebook::train(stacked, co);
    cb.save(out);
    std::cerr << "codebook of " << cb.size() << " words from " << rows << " descriptors -> " << out << "\n";
    return 0;
}

int descriptor_command(const std::string& in, const std::string& out, const ViewCommandOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    views::Codebook cb;
    if (!o.codebook.empty()) cb = views::Codebook::load(o.codebook);
    const views::ViewSet vs = views_of(in, o);
    views::ModelDescriptor d;
    d.source = in;
    d.views = static_cast<int>(vs.images.size());
    d.image_size = o.image_size;
    d.keypoints_per_view = vs.keypoint_counts();
    if (!o.codebook.empty()) {
        d.codebook_words = cb.size();
        d.histograms = views::view_histograms(vs, cb);
    } else {
        d.raw = vs.features;
    }
    views::write_descriptor(out, d);
    const int total = std::accumulate(d.keypoints_per_view.begin(), d.keypoints_per_view.end(), 0);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (o.json)
        std::cout << "{\"views\": " << d.views << ", \"keypoints\": " << total << ", \"codebook_words\": "
                  << d.codebook_words << ", \"seconds\": " << secs << "}\n";
    return 0;
}

int distance_command(const std::string& out, const std::vector<std::string>& descriptors, const ViewCommandOptions& o) {
    if (descriptors.size() < 2) throw InputError("distance needs at least two descriptor files");
    std::vector<std::vector<views::Histogram>> models;
    int words = -1;
    for (const auto& path : descriptors) {
        views::ModelDescriptor d = views::read_descriptor(path);
        if (d.codebook_words == 0)
            throw InputError("'" + path + "' holds raw SIFT features: make descriptors with --codebook");
        if (words >= 0 && d.codebook_words != words)
            throw InputError("'" + path + "' uses a codebook of " + std::to_string(d.codebook_words) +
                             " words, the others " + std::to_string(words));
        words = d.codebook_words;
        models.push_back(std::move(d.histograms));
    }
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::MatrixXf D = views::distance_matrix(models, views::rotation_view_maps(), o.threads);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_distance_matrix(D, out, out + ".csv");
    std::cerr << D.rows() << " x " << D.cols() << " clock-matching distances in " << secs << " s -> " << out
              << " (float32 row-major) and " << out << ".csv\n";
    return 0;
}

}  // namespace canonform::cli
