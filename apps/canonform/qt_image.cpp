// SPDX-License-Identifier: GPL-3.0-or-later
#include "qt_image.h"

#include "canonform/io/files.h"

#include <QCoreApplication>
#include <QGuiApplication>
#include <QPainter>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace canonform::cli {

void ensure_gui_application() {
    if (QCoreApplication::instance()) return;
    if (!std::getenv("QT_QPA_PLATFORM")) setenv("QT_QPA_PLATFORM", "offscreen", 1);
    static int argc = 1;
    static char arg0[] = "canonform";
    static char* argv[] = {arg0, nullptr};
    static QGuiApplication app(argc, argv);
}

void save_png(const QImage& img, const std::string& path) {
    const std::string tmp = io::temporary_path_for(path);
    if (!img.save(QString::fromStdString(tmp), "PNG")) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path + "'");
    }
    io::commit_file(tmp, path);
}

QImage white_canvas(int width, int height) {
    ensure_gui_application();
    QImage img(width, height, QImage::Format_RGB888);
    img.fill(Qt::white);
    return img;
}

void set_label_font(QPainter& p, int pixels) {
    QFont font = p.font();
    font.setPixelSize(pixels);
    p.setFont(font);
    p.setPen(Qt::black);
}

}  // namespace canonform::cli
