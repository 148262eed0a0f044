// SPDX-License-Identifier: GPL-3.0-or-later
#include "picture.h"

#include "qt_image.h"
#include "render.h"

#include "canonform/common/errors.h"
#include "canonform/views/view_descriptor.h"

#include <QFont>
#include <QImage>
#include <QPainter>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <tuple>

namespace canonform {

namespace {

Eigen::MatrixXd colours_from(const Eigen::VectorXd& q, Eigen::Index n) {
    Eigen::MatrixXd C(n, 3);
    if (q.size() != n) {
        C.rowwise() = Eigen::RowVector3d(0.8, 0.8, 0.8);
        return C;
    }
    const double lo = q.minCoeff(), hi = q.maxCoeff();
    for (Eigen::Index k = 0; k < n; ++k)
        C.row(k) = render::ramp(hi > lo ? (q(k) - lo) / (hi - lo) : 0.5).transpose();
    return C;
}

QImage panel_image(const Mesh& m, const Eigen::MatrixXd& C, const Eigen::MatrixXd& points, int size) {
    render::Image img(size, size);
    const render::View view = render::fit_view(m.V, size, size, 16);
    render::draw_mesh(img, view, m.V, m.F, C);
    if (points.rows()) {
        const double diag = (m.V.colwise().maxCoeff() - m.V.colwise().minCoeff()).norm();
        render::draw_points(img, view, points, Eigen::Vector3d(0.95, 0.1, 0.1), std::max(3, size / 90),
                            0.01 * diag);
    }
    QImage q(img.rgb.data(), size, size, 3 * size, QImage::Format_RGB888);
    return q.copy();  // own the pixels
}

/// Positions of the canonical form at the vertices of `mesh` that coincide with `points`.
Eigen::MatrixXd map_points(const Mesh& mesh, const Eigen::MatrixXd& points, const Eigen::MatrixXd& target) {
    std::map<std::tuple<double, double, double>, Eigen::Index> where;
    for (Eigen::Index k = 0; k < mesh.V.rows(); ++k) where[{mesh.V(k, 0), mesh.V(k, 1), mesh.V(k, 2)}] = k;
    Eigen::MatrixXd out(points.rows(), 3);
    Eigen::Index n = 0;
    for (Eigen::Index k = 0; k < points.rows(); ++k) {
        const auto it = where.find({points(k, 0), points(k, 1), points(k, 2)});
        if (it != where.end() && it->second < target.rows()) out.row(n++) = target.row(it->second);
    }
    return out.topRows(n);
}

}  // namespace

void check_drawable(const std::string& path, const Mesh& m, const Eigen::VectorXd& quality) {
    const std::string where = "'" + path + "': ";
    if (m.V.rows() == 0) throw InputError(where + "the mesh is empty: it has no vertices, nothing to draw");
    if (m.F.rows() == 0)
        throw InputError(where + "the mesh has " + std::to_string(m.V.rows()) +
                         " vertices and no faces (a point cloud): the picture draws a triangle mesh");
    if (!m.V.allFinite()) throw InputError(where + "the mesh has NaN or infinite coordinates");
    if (!((m.V.colwise().maxCoeff() - m.V.colwise().minCoeff()).stableNorm() > 0))
        throw InputError(where + "all " + std::to_string(m.V.rows()) +
                         " vertices are at one point: nothing to draw");
    if (quality.size() && !quality.allFinite())
        throw InputError(where + "the vertex quality has NaN or infinite values");
}

void check_points(const std::string& path, const Eigen::MatrixXd& P) {
    if (P.rows() == 0) throw InputError("'" + path + "': no feature points in the file");
    if (!P.allFinite()) throw InputError("'" + path + "': feature points with NaN or infinite coordinates");
}

void write_picture(const std::string& path, const PictureInputs& in, int panel) {
    if (panel < 64 || panel > 4096)
        throw std::runtime_error("the panel size must be between 64 and 4096 pixels");
    cli::ensure_gui_application();

    struct Panel {
        QImage image;
        QString label;
    };
    std::vector<Panel> panels;
    const Eigen::MatrixXd C = colours_from(in.mesh_quality, in.mesh.V.rows());
    panels.push_back({panel_image(in.mesh, C, Eigen::MatrixXd(), panel),
                      in.mesh_quality.size() ? "mesh: conformal factor" : "mesh"});
    if (in.points.rows()) {
        const Eigen::MatrixXd grey = colours_from(Eigen::VectorXd(), in.mesh.V.rows());
        panels.push_back({panel_image(in.mesh, grey, in.points, panel),
                          QString("feature points (%1)").arg(in.points.rows())});
    }
    if (in.canonical.V.rows()) {
        if (in.canonical.V.rows() != in.mesh.V.rows())
            throw std::runtime_error("the canonical form and the mesh have different vertex counts");
        const Eigen::MatrixXd Cc = colours_from(in.canonical_quality, in.canonical.V.rows());
        const Eigen::MatrixXd P =
            in.points.rows() ? map_points(in.mesh, in.points, in.canonical.V) : Eigen::MatrixXd();
        panels.push_back({panel_image(in.canonical, Cc, P, panel), "canonical form"});
    }
    const int label_h = 28;
    QImage out = cli::white_canvas(static_cast<int>(panels.size()) * panel, panel + label_h);
    QPainter p(&out);
    cli::set_label_font(p, 16);
    for (size_t k = 0; k < panels.size(); ++k) {
        const int x = static_cast<int>(k) * panel;
        p.drawImage(x, label_h, panels[k].image);
        p.drawText(QRect(x, 0, panel, label_h), Qt::AlignCenter, panels[k].label);
        if (k > 0) p.drawLine(x, label_h, x, panel + label_h);
    }
    p.end();
    cli::save_png(out, path);
}

void write_view_images(const std::string& dir, const views::ViewSet& vs) {
    using namespace cli;
    const int cols = 11, thumb = 128, label = 16;
    QImage sheet = white_canvas(cols * thumb, 6 * (thumb + label));
    QPainter p(&sheet);
    set_label_font(p, 11);
    const auto counts = vs.keypoint_counts();
    for (size_t k = 0; k < vs.images.size(); ++k) {
        const auto g = vs.images[k].gray();
        const int n = vs.images[k].size;
        const QImage img = QImage(g.data(), n, n, n, QImage::Format_Grayscale8).copy();
        char name[32];
        std::snprintf(name, sizeof name, "/view_%02zu.png", k);
        save_png(img, dir + name);
        const int x = static_cast<int>(k % cols) * thumb, y = static_cast<int>(k / cols) * (thumb + label);
        p.drawImage(QRect(x, y + label, thumb, thumb), img);
        p.drawText(QRect(x, y, thumb, label), Qt::AlignCenter,
                   QString("view %1: %2 keypoints").arg(k).arg(counts[k]));
    }
    p.end();
    save_png(sheet, dir + "/contact_sheet.png");
}

}  // namespace canonform
