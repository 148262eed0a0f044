// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: MeshLab 2022.02 and later driven the way pymeshlab drives them, in C++: shared by the
// pymeshlab harness (tests/pymeshlab_harness.cpp, against the double meshlab-common built here)
// and the headless runner canonform-meshlab (apps/canonform-meshlab/, against the installed
// MeshLab's own libmeshlab-common.so).
//
// Every step is MeshLab's own code, called as pymeshlab 2022.2 / 2025.7 calls it:
//   load_plugin(path)        pymeshlab.load_plugin: PluginManager::checkPlugin (a Qt plugin, a
//                            MeshLab plugin, the precision and the "YYYY.0" version prefix, the
//                            filter checks), PluginManager::loadPlugin, and the Python names into
//                            MeshLab's pymeshlab::FunctionSet;
//   load_plugins(dir)        what pymeshlab and MeshLab do at start: PluginManager::loadPlugins;
//   MeshSet::apply_filter    MeshSet.apply_filter(name, **kwargs): the Function of that Python
//                            name, the plugin's initParameterList, each keyword set on its
//                            parameter as pymeshlab converts it, (2025.7:) isFilterApplicable,
//                            getRequirements, applyFilter; its map is the returned dict;
//   MeshSet::load / save     load_new_mesh / save_current_mesh through MeshLab's IO plugins.
// Needs CANONFORM_MESHLAB_API >= 2022 (the FilterPlugin API).
#pragma once

#include <common/ml_document/mesh_document.h>
#include <common/mlexception.h>
#include <common/plugins/interfaces/filter_plugin.h>  // QVariant of Eigen::VectorXd (a returned vector)

#include <QVariant>

#include <Eigen/Core>

#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace canonform::meshlab {

/// Text from a command line, converted by the type of the parameter it is given to (bool:
/// true/false/1/0, int, float, enum by name or index, string as is).
struct Text {
    std::string text;
};
/// A keyword argument's value: what Python passes (bool, int, float, str), or Text.
using PyValue = std::variant<bool, int, double, std::string, Text>;
using Kwargs = std::vector<std::pair<std::string, PyValue>>;
/// What apply_filter returns (pymeshlab converts it to a dict).
using Dict = std::map<std::string, QVariant>;

/// pymeshlab.load_plugin(filename): throws MLException with MeshLab's reason when refused.
void load_plugin(const std::string& filename);

/// Loads every plugin of `dir` with MeshLab's PluginManager::loadPlugins, then builds the function
/// set of Python names from them. Returns MeshLab's message about the plugins it refused (the
/// others are loaded), or "".
std::string load_plugins(const std::string& dir);

/// A pymeshlab.MeshSet: a MeshDocument with its methods.
class MeshSet : public MeshDocument {
public:
    /// add_mesh(Mesh(V, F)): a new current mesh named `name`.
    void add_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const QString& name);
    /// load_new_mesh(path): through the IO plugin of its extension; the new mesh is current.
    void load_new_mesh(const std::string& path);
    /// Saves mesh `m` to `path` (IO plugin of its extension) with every attribute the mesh has
    /// and the format can hold (vertex quality, colours, normals, texture coordinates).
    void save_mesh(const std::string& path, MeshModel& m);
    /// apply_filter(filtername, **kwargs)
    Dict apply_filter(const std::string& filtername, const Kwargs& kwargs);
};

/// The dict as JSON: ints, floats (17 digits), bools; vectors in full, or, with
/// `vector_summary`, as {"length": n, "sum": s}.
std::string to_json(const Dict& d, bool vector_summary = false);

}  // namespace canonform::meshlab
