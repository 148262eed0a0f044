// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: `canonform grid` - original meshes beside their canonical forms, as the paper's
// Figs. 8 (one model per class, a row per method) and 9 (one class in several poses).
#pragma once

#include <string>
#include <vector>

namespace canonform::cli {

struct GridOptions {
    std::string run;  ///< a `canonform retrieve` run folder (RUN/collection.csv, RUN/METHOD/forms/)
    std::vector<std::string> methods;  ///< method folders of the run, one row each ("" = every one but none);
                                       ///< "DIR=LABEL" labels the row LABEL
    std::string cls;   ///< "" = the first model of every class (Fig. 8); else models of this class (Fig. 9)
    int columns = 10;  ///< at most this many columns
    int panel = 150;   ///< pixels per panel
};

/// Renders the grid into a PNG at `path` (written atomically): the first row the original meshes
/// (RUN/none/forms/ if the run has them, i.e. after --simplify/--noise, else the collection's
/// meshes), then one row per method with the forms of the same models. Every vertex is coloured
/// by its height along the original mesh's longest principal axis, so colours show which part
/// went where. A form missing from the run is drawn as an empty panel marked "missing".
/// Returns the number of columns drawn. Throws InputError on an unusable run folder.
int write_grid(const std::string& path, const GridOptions& o);

}  // namespace canonform::cli
