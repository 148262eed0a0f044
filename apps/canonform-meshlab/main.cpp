// SPDX-License-Identifier: GPL-3.0-or-later
// canonform-meshlab: applies a MeshLab filter to a mesh file, headless, with the installed
// MeshLab's own library (MeshLab 2022.02 and later have no meshlabserver).
//
//   canonform-meshlab IN OUT --filter NAME [--param key=value]... [--json FILE]
//                     [--layer result|current|N] [--plugin FILE]... [--plugins DIR]
//   canonform-meshlab --list
//
// Everything goes through the installed libmeshlab-common.so, as MeshLab and pymeshlab do it
// (canonform::meshlab::MeshSet, filter_canonical/meshlab_meshset.h): PluginManager::loadPlugins on
// MeshLab's plugin folder (its checks of precision, version and filters), the Python names of
// MeshLab's function set, IN read and OUT written by MeshLab's IO plugins, parameters converted
// by their MeshLab type (bool, int, float, enum by name or index, string). The filter's returned
// values are printed as JSON (and written to --json FILE); MeshLab prints its log ("LOG: ...") on
// stderr. OUT is the
// layer the filter made (the last new one), else the current mesh (--layer), written atomically.
// Exit status: 0 done, 1 refused or failed (the reason on stderr, no OUT written), 2 usage.
#include "canonform/meshlab/meshlab_meshset.h"

#include <common/globals.h>
#include <common/plugins/plugin_manager.h>
#include <common/python/function_set.h>

#include <CLI/CLI.hpp>

#include <QApplication>
#include <QDir>
#include <QFileInfo>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#ifndef CANONFORM_MESHLAB_PLUGIN_DIR
#error "CANONFORM_MESHLAB_PLUGIN_DIR: the installed MeshLab's plugin folder"
#endif

namespace {

namespace fs = std::filesystem;
using canonform::meshlab::MeshSet;

int fail(const std::string& why) {
    std::fprintf(stderr, "canonform-meshlab: %s\n", why.c_str());
    return 1;
}

/// The plugin files named in MeshLab's message about the plugins it refused.
std::string refused_files(const std::string& message) {
    std::string files;
    std::size_t at = 0;
    while ((at = message.find('\t', at)) != std::string::npos) {
        const std::size_t colon = message.find(':', at);
        if (colon == std::string::npos) break;
        files += (files.empty() ? "" : ", ") + message.substr(at + 1, colon - at - 1);
        at = colon;
    }
    return files;
}

/// Every filter MeshLab's function set knows, with its parameters (Python names and defaults).
void list_filters() {
    const pymeshlab::FunctionSet& fs = pymeshlab::functionSetInstance();
    for (const std::string& name : fs.pythonFilterFunctionNames()) {
        const pymeshlab::Function& f = fs.filterFunction(QString::fromStdString(name));
        std::printf("%s", name.c_str());
        for (const pymeshlab::FunctionParameter& p : f)
            std::printf(" %s", p.pythonName().toStdString().c_str());
        std::printf("\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Applies a MeshLab filter (by its Python name, as in pymeshlab) to a mesh file, with the installed "
        "MeshLab " +
        ::meshlab::meshlabVersion() +
        "'s own library and plugins; prints the filter's returned values as JSON."};
    std::string in, out, filter, json_file, layer = "result", plugin_dir = CANONFORM_MESHLAB_PLUGIN_DIR;
    std::vector<std::string> params, plugins;
    bool list = false, verbose = false;
    app.add_option("IN", in, "input mesh (any format MeshLab reads: PLY, OFF, OBJ, STL, ...)");
    app.add_option("OUT", out, "output mesh (format by extension)");
    app.add_option("--filter", filter, "the filter's Python name, e.g. generate_euclidean_canonical_form");
    app.add_option("--param", params, "a parameter as key=value (Python name; enums by name or index)");
    app.add_option("--json", json_file, "also write the returned values (JSON) to this file");
    app.add_option("--layer", layer,
                   "which layer to save: result (the last layer the filter made, else the current "
                   "mesh), current, or a layer index")
        ->capture_default_str();
    app.add_option("--plugin", plugins, "load this plugin file too (as pymeshlab.load_plugin)");
    app.add_option("--plugins", plugin_dir, "MeshLab's plugin folder")->capture_default_str();
    app.add_flag("--list", list, "list the filters (Python names and parameters) and exit");
    app.add_flag("--verbose", verbose, "say why MeshLab refused any of its plugins");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    if (!list && (in.empty() || out.empty() || filter.empty())) {
        std::fprintf(stderr, "canonform-meshlab: IN, OUT and --filter are required (--help)\n");
        return 2;
    }
    canonform::meshlab::Kwargs kwargs;
    for (const std::string& p : params) {
        const auto eq = p.find('=');
        if (eq == std::string::npos || eq == 0) {
            std::fprintf(stderr, "canonform-meshlab: --param %s: expected key=value\n", p.c_str());
            return 2;
        }
        kwargs.emplace_back(p.substr(0, eq), canonform::meshlab::Text{p.substr(eq + 1)});
    }

    // MeshLab's plugins expect a GUI application (some make pixmaps when loaded); headless, on
    // Qt's offscreen platform unless the caller chose another
    if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
    QApplication qapp(argc, argv);
    try {
        // MeshLab's plugins, with MeshLab's checks; a refused plugin is reported, the others load
        const std::string refused = canonform::meshlab::load_plugins(plugin_dir);
        if (!refused.empty()) {
            if (verbose)
                std::fprintf(stderr, "canonform-meshlab: %s\n", refused.c_str());
            else
                std::fprintf(stderr,
                             "canonform-meshlab: note: MeshLab did not load %s (--verbose says why)\n",
                             refused_files(refused).c_str());
        }
        for (const std::string& p : plugins) canonform::meshlab::load_plugin(p);
        if (list) {
            list_filters();
            return 0;
        }
        if (!pymeshlab::functionSetInstance().containsFilterFunction(QString::fromStdString(filter)))
            return fail("no filter named '" + filter + "' in MeshLab " + ::meshlab::meshlabVersion() +
                        " (loaded from " + plugin_dir + "; --list shows the names)");

        MeshSet ms;
        ms.load_new_mesh(in);
        std::set<int> before;
        for (const MeshModel& m : ms.meshIterator()) before.insert(m.id());
        const int current = ms.mm() ? ms.mm()->id() : -1;

        const canonform::meshlab::Dict values = ms.apply_filter(filter, kwargs);

        MeshModel* target = nullptr;
        if (layer == "result" || layer == "current") {
            if (current >= 0) target = ms.getMesh(static_cast<unsigned>(current));
            if (layer == "result")
                for (MeshModel& m : ms.meshIterator())
                    if (!before.count(m.id())) target = &m;
        } else {
            int index = -1, k = 0;
            try {
                index = std::stoi(layer);
            } catch (const std::exception&) {
                return fail("--layer " + layer + ": expected result, current or a layer index");
            }
            for (MeshModel& m : ms.meshIterator())
                if (k++ == index) target = &m;
            if (!target)
                return fail("--layer " + layer + ": the document has " + std::to_string(ms.meshNumber()) +
                            " layers");
        }
        if (!target) return fail("the filter left no mesh to save");

        // atomic: written next to OUT under a temporary name (same extension), then renamed
        const fs::path out_path(out);
        const fs::path tmp = out_path.parent_path() / ("." + out_path.stem().string() + ".canonform-tmp" +
                                                       out_path.extension().string());
        try {
            ms.save_mesh(tmp.string(), *target);
            fs::rename(tmp, out_path);
        } catch (...) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw;
        }
        std::fprintf(stderr, "canonform-meshlab: saved layer '%s' (%d vertices, %d faces) to %s\n",
                     target->label().toStdString().c_str(), target->cm.vn, target->cm.fn, out.c_str());

        const std::string json = canonform::meshlab::to_json(values);
        std::printf("%s\n", json.c_str());
        if (!json_file.empty()) {
            std::ofstream o(json_file);
            o << json << "\n";
            if (!o) return fail("cannot write " + json_file);
        }
        return 0;
    } catch (const std::exception& e) {
        return fail(e.what());
    }
}
