// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: what the picture-writing commands (picture, grid, views) share on the Qt side.
#pragma once

#include <QImage>
#include <QPainter>

#include <string>

namespace canonform::cli {

/// Makes sure a QGuiApplication exists (Qt's fonts need one), on the offscreen platform unless
/// QT_QPA_PLATFORM says otherwise: no X server needed. One per process, kept until exit.
void ensure_gui_application();

/// Writes `img` as a PNG at `path` atomically (temporary file, then rename); throws
/// std::runtime_error naming the path if it cannot be written.
void save_png(const QImage& img, const std::string& path);

/// A white RGB image (after ensure_gui_application(), which its labels need).
QImage white_canvas(int width, int height);

/// Labels in black at `pixels` pixels high.
void set_label_font(QPainter& p, int pixels);

}  // namespace canonform::cli
