// SPDX-License-Identifier: GPL-3.0-or-later
#include "pr_plot.h"

#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/files.h"
#include "qt_image.h"

#include <QFontMetrics>
#include <QImage>
#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>

namespace canonform::cli {

namespace {

/// A number of a pr.csv cell, in [0, 1]; InputError naming the file and line otherwise.
double probability(const std::string& cell, const std::string& path, size_t line) {
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v) || v < 0 || v > 1)
        throw InputError(path + ": line " + std::to_string(line) + ": '" + cell +
                         "' is not a number from 0 to 1 (rows are recall,precision)");
    return v;
}

/// Ten colours that stay apart on white (the usual categorical palette of plotting programs).
const QColor kColours[] = {QColor(31, 119, 180),  QColor(255, 127, 14),  QColor(44, 160, 44),
                           QColor(214, 39, 40),   QColor(148, 103, 189), QColor(140, 86, 75),
                           QColor(227, 119, 194), QColor(127, 127, 127), QColor(188, 189, 34),
                           QColor(23, 190, 207)};

}  // namespace

std::vector<PrCurve> read_pr_curves(const std::string& run, const std::string& prefix) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(run, ec))
        throw InputError("'" + run + "' is not a folder (a `canonform retrieve` run folder)");
    std::vector<std::string> folders;
    for (const fs::directory_entry& d : fs::directory_iterator(run, ec))
        if (d.is_directory(ec) && io::is_file((d.path() / "pr.csv").string()))
            folders.push_back(d.path().filename().string());
    std::sort(folders.begin(), folders.end());
    std::vector<PrCurve> curves;
    for (const std::string& f : folders) {
        const std::string path = run + "/" + f + "/pr.csv";
        const auto rows = io::read_csv(path);
        PrCurve c{prefix.empty() ? f : prefix + " " + f, {}, {}};
        for (size_t r = 0; r < rows.size(); ++r) {
            if (r == 0 && !rows[r].empty() && rows[r][0] == "recall") continue;  // the header
            if (rows[r].size() != 2)
                throw InputError(path + ": line " + std::to_string(r + 1) + " has " +
                                 std::to_string(rows[r].size()) + " cells, not recall,precision");
            c.recall.push_back(probability(rows[r][0], path, r + 1));
            c.precision.push_back(probability(rows[r][1], path, r + 1));
        }
        if (c.recall.empty()) throw InputError(path + ": no point (rows are recall,precision)");
        curves.push_back(std::move(c));
    }
    return curves;
}

void write_pr_plot(const std::string& path, const std::vector<PrCurve>& curves, const std::string& title) {
    if (curves.empty()) throw InputError("no precision-recall curve to draw (no METHOD/pr.csv in the run)");
    const int width = 620, height = 470;
    const int left = 62, right = 16, top = 34, bottom = 48;  // the plot area's margins
    QImage img = white_canvas(width, height);
    QPainter p(&img);
    p.setRenderHint(QPainter::Antialiasing);
    const double w = width - left - right, h = height - top - bottom;
    const auto at = [&](double x, double y) { return QPointF(left + x / 1.02 * w, top + h - y / 1.02 * h); };

    set_label_font(p, 13);
    const QFontMetrics fm(p.font());
    for (int k = 0; k <= 5; ++k) {  // grid lines and tick labels every 0.2
        const double v = 0.2 * k;
        p.setPen(QPen(QColor(225, 225, 225), 1));
        p.drawLine(at(v, 0), at(v, 1.02));
        p.drawLine(at(0, v), at(1.02, v));
        p.setPen(Qt::black);
        const QString t = QString::number(v, 'f', 1);
        const QPointF x = at(v, 0), y = at(0, v);
        p.drawText(QPointF(x.x() - fm.horizontalAdvance(t) / 2.0, top + h + fm.height()), t);
        p.drawText(QPointF(left - 6 - fm.horizontalAdvance(t), y.y() + fm.ascent() / 2.0 - 1), t);
    }
    p.setPen(QPen(Qt::black, 1));
    p.drawRect(QRectF(left, top, w, h));
    p.drawText(QPointF(left + w / 2 - fm.horizontalAdvance("recall") / 2.0, height - 10), "recall");
    p.save();
    p.translate(16, top + h / 2 + fm.horizontalAdvance("precision") / 2.0);
    p.rotate(-90);
    p.drawText(QPointF(0, 0), "precision");
    p.restore();
    const QString t = QString::fromStdString(title);
    p.drawText(QPointF(left + w / 2 - fm.horizontalAdvance(t) / 2.0, top - 10), t);

    p.setClipRect(QRectF(left, top, w, h));
    for (size_t c = 0; c < curves.size(); ++c) {
        const QColor colour = kColours[c % 10];
        QPainterPath line;
        for (size_t k = 0; k < curves[c].recall.size(); ++k) {
            const QPointF q = at(curves[c].recall[k], curves[c].precision[k]);
            if (k == 0)
                line.moveTo(q);
            else
                line.lineTo(q);
        }
        p.setPen(QPen(colour, 2));
        p.setBrush(Qt::NoBrush);
        p.drawPath(line);
        p.setBrush(colour);
        for (size_t k = 0; k < curves[c].recall.size(); ++k)
            p.drawEllipse(at(curves[c].recall[k], curves[c].precision[k]), 3, 3);
    }
    p.setClipping(false);

    // The legend, in the corner of the plot that covers the fewest points of the curves (the first
    // of bottom left, bottom right, top right, top left on a tie).
    int legend_w = 0;
    for (const PrCurve& c : curves)
        legend_w = std::max(legend_w, fm.horizontalAdvance(QString::fromStdString(c.label)));
    const int row = fm.height() + 4, lw = legend_w + 46, lh = row * static_cast<int>(curves.size()) + 8;
    const QRectF corners[] = {QRectF(left + 8, top + h - 8 - lh, lw, lh),
                              QRectF(left + w - 8 - lw, top + h - 8 - lh, lw, lh),
                              QRectF(left + w - 8 - lw, top + 8, lw, lh), QRectF(left + 8, top + 8, lw, lh)};
    QRectF box = corners[0];
    size_t fewest = SIZE_MAX;
    for (const QRectF& corner : corners) {
        size_t covered = 0;
        for (const PrCurve& c : curves)
            for (size_t k = 0; k < c.recall.size(); ++k)
                covered += corner.contains(at(c.recall[k], c.precision[k]));
        if (covered < fewest) {
            fewest = covered;
            box = corner;
        }
    }
    p.setPen(QPen(QColor(200, 200, 200), 1));
    p.setBrush(QColor(255, 255, 255, 230));
    p.drawRoundedRect(box, 3, 3);
    for (size_t c = 0; c < curves.size(); ++c) {
        const double y = box.top() + 4 + row * (c + 0.5);
        p.setPen(QPen(kColours[c % 10], 2));
        p.drawLine(QPointF(box.left() + 8, y), QPointF(box.left() + 34, y));
        p.setBrush(kColours[c % 10]);
        p.drawEllipse(QPointF(box.left() + 21, y), 3, 3);
        p.setPen(Qt::black);
        p.drawText(QPointF(box.left() + 40, y + fm.ascent() / 2.0 - 1),
                   QString::fromStdString(curves[c].label));
    }
    p.end();
    save_png(img, path);
}

}  // namespace canonform::cli
