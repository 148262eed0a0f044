// SPDX-License-Identifier: GPL-3.0-or-later
#include "grid.h"

#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "qt_image.h"
#include "render.h"

#include <QFont>
#include <QImage>
#include <QPainter>

#include <Eigen/Eigenvalues>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

namespace canonform::cli {

namespace {

struct Entry {
    std::string name, label, path;
};

std::vector<Entry> read_collection(const std::string& run) {
    const std::string path = run + "/collection.csv";
    if (!io::is_file(path))
        throw InputError("'" + run + "' has no collection.csv: is it a `canonform retrieve` run folder?");
    std::vector<Entry> out;
    const auto rows = io::read_csv(path);
    for (size_t r = 1; r < rows.size(); ++r) {  // row 0: the header
        if (rows[r].size() < 3) continue;
        Entry e{rows[r][0], rows[r][1], rows[r][2]};
        for (size_t k = 3; k < rows[r].size(); ++k) e.path += "," + rows[r][k];
        out.push_back(e);
    }
    return out;
}

/// Position of every vertex along the longest principal axis of `ref`, scaled to [0, 1].
Eigen::VectorXd heights(const Eigen::MatrixXd& ref) {
    const Eigen::MatrixXd X = ref.rowwise() - ref.colwise().mean();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(X.transpose() * X);
    Eigen::VectorXd t = X * es.eigenvectors().col(2);
    const double lo = t.minCoeff(), hi = t.maxCoeff();
    return hi > lo ? Eigen::VectorXd((t.array() - lo) / (hi - lo)) : Eigen::VectorXd::Constant(t.size(), 0.5);
}

/// The panel: the mesh seen along its smallest principal axis, turned so that the vertices with
/// larger `t` are (on average) higher up in the picture, coloured by `t` (grey if `t` is empty).
QImage panel_image(const Mesh& m, const Eigen::VectorXd& t, int size) {
    render::Image img(size, size);
    render::View view = render::fit_view(m.V, size, size, 6);
    Eigen::MatrixXd C(m.V.rows(), 3);
    if (t.size() == m.V.rows()) {
        const Eigen::VectorXd up = m.V * view.R.row(1).transpose();
        const double corr = ((up.array() - up.mean()) * (t.array() - t.mean())).sum();
        if (corr < 0) {  // half a turn about the viewing axis, about the image centre
            view.R.row(0) *= -1;
            view.R.row(1) *= -1;
            view.offset = Eigen::Vector2d(size, size) - view.offset;
        }
        for (Eigen::Index k = 0; k < m.V.rows(); ++k) C.row(k) = render::ramp(t(k)).transpose();
    } else {
        C.rowwise() = Eigen::RowVector3d(0.75, 0.75, 0.75);
    }
    render::draw_mesh(img, view, m.V, m.F, C);
    return QImage(img.rgb.data(), size, size, 3 * size, QImage::Format_RGB888).copy();
}

}  // namespace

int write_grid(const std::string& path, const GridOptions& o) {
    if (o.panel < 32 || o.panel > 2048) throw InputError("the panel size must be between 32 and 2048 pixels");
    if (o.columns < 1) throw InputError("the number of columns must be positive");
    const std::vector<Entry> coll = read_collection(o.run);
    std::vector<std::string> methods = o.methods;
    if (methods.empty()) {
        for (const auto& d : std::filesystem::directory_iterator(o.run))
            if (d.is_directory() && d.path().filename() != "none" &&
                io::is_file(d.path().string() + "/models.csv"))
                methods.push_back(d.path().filename().string());
        std::sort(methods.begin(), methods.end());
    }
    // "DIR=LABEL" shows the method folder DIR under another row label.
    std::vector<std::string> row_labels;
    for (auto& m : methods) {
        const auto eq = m.find('=');
        row_labels.push_back(eq == std::string::npos ? m : m.substr(eq + 1));
        if (eq != std::string::npos) m = m.substr(0, eq);
    }
    for (const auto& m : methods)
        if (!std::filesystem::is_directory(o.run + "/" + m + "/forms"))
            throw InputError("the run '" + o.run + "' has no method '" + m + "' (no " + m + "/forms/)");
    if (methods.empty()) throw InputError("the run '" + o.run + "' has no canonical forms to show");
    const std::string original_dir = o.run + "/none/forms";
    const bool simplified = std::filesystem::is_directory(original_dir);

    // Columns: the first model of each class (in collection order), or the models of one class.
    std::vector<Entry> cols;
    for (const Entry& e : coll) {
        if (static_cast<int>(cols.size()) >= o.columns) break;
        if (!o.cls.empty()) {
            if (e.label == o.cls) cols.push_back(e);
            continue;
        }
        bool seen = false;
        for (const Entry& c : cols) seen |= c.label == e.label;
        if (!seen) cols.push_back(e);
    }
    if (cols.empty()) throw InputError("the run '" + o.run + "' has no model of class '" + o.cls + "'");

    const int P = o.panel, label_w = 130, label_h = 22;
    const int rows = 1 + static_cast<int>(methods.size());
    QImage out = white_canvas(label_w + static_cast<int>(cols.size()) * P, label_h + rows * P);
    QPainter p(&out);
    set_label_font(p, 13);
    for (size_t c = 0; c < cols.size(); ++c) {
        const int x = label_w + static_cast<int>(c) * P;
        p.drawText(QRect(x, 0, P, label_h), Qt::AlignCenter,
                   QString::fromStdString(o.cls.empty() ? cols[c].label : cols[c].name));
        Mesh orig;
        const std::string op = simplified ? original_dir + "/" + cols[c].name + ".ply" : cols[c].path;
        if (io::is_file(op)) orig = io::read_mesh(op);
        const Eigen::VectorXd t = orig.V.rows() ? heights(orig.V) : Eigen::VectorXd();
        for (int r = 0; r < rows; ++r) {
            const int y = label_h + r * P;
            Mesh m;
            if (r == 0) {
                m = orig;
            } else {
                const std::string fp =
                    o.run + "/" + methods[static_cast<size_t>(r - 1)] + "/forms/" + cols[c].name + ".ply";
                if (io::is_file(fp)) m = io::read_mesh(fp);
            }
            if (m.V.rows() == 0) {
                p.drawText(QRect(x, y, P, P), Qt::AlignCenter, "missing");
                continue;
            }
            p.drawImage(x, y, panel_image(m, t, P));
        }
    }
    for (int r = 0; r < rows; ++r) {
        const std::string name = r == 0 ? std::string("original") : row_labels[static_cast<size_t>(r - 1)];
        p.drawText(QRect(4, label_h + r * P, label_w - 8, P),
                   Qt::AlignVCenter | Qt::AlignLeft | Qt::TextWordWrap, QString::fromStdString(name));
        if (r > 0) p.drawLine(label_w, label_h + r * P, out.width(), label_h + r * P);
    }
    p.end();
    save_png(out, path);
    return static_cast<int>(cols.size());
}

}  // namespace canonform::cli
