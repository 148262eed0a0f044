// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the types of a plugin's filter table, shared by both plugins and every MeshLab API
// adapter.
//
// A plugin describes its filters once, as a table of FilterSpec (names, classes, Python names,
// parameters, what a filter reads and changes) in plain C++ (no Qt, no MeshLab). Every MeshLab API
// adapter (meshlab2020_adapter for MeshFilterInterface, meshlab2022_adapter for FilterPlugin),
// the shipped .mlx scripts, the pymeshlab harness, the tests and the parameter listing of the
// docs read the same table. A filter's parameters are the library's Parameter definitions
// (common/parameters.h) - a method filter's are its methods' (method_registry.h) - shown by MeshLab
// as RichBool (Bool), RichInt (Int), RichFloat (Float), RichEnum (Choice, by index) and RichString
// (Text); MeshLab's types carry no range, so the tooltip states it and the action checks it.
#pragma once

#include "canonform/common/errors.h"
#include "canonform/common/parameters.h"

#include <functional>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace canonform::meshlab {

/// Where an action reports: a log line, and progress.
struct ActionContext {
    std::function<void(const std::string&)> log;
    ProgressFn progress;
};

/// One output of an action: a real number, a count, a flag or a vector. MeshLab 2022.02's
/// adapter returns them from applyFilter, and pymeshlab 2022.2 to Python as float, int, bool and
/// numpy array (a QVariant of double, int, bool or Eigen::VectorXd); 2020.09's API has no outputs.
using OutputValue = std::variant<double, int, bool, std::vector<double>>;

/// Named outputs of an action (iterations, stresses, counts, seconds, descriptor).
using ActionOutputs = std::map<std::string, OutputValue>;

/// Parameter values by name as MeshLab hands them over (bool: 0/1, enum: index; strings apart).
struct ParamValues {
    std::map<std::string, double> values;
    std::map<std::string, std::string> strings;
    double get(const std::string& name) const;
    int get_int(const std::string& name) const { return static_cast<int>(get(name)); }
    bool get_bool(const std::string& name) const { return get(name) != 0; }
    const std::string& get_string(const std::string& name) const;
    /// The values of those of `params` that are present, as the parameters' texts (a number with 17
    /// significant digits, an enum's choice by name, a switch as true/false): checked by Settings.
    std::vector<std::pair<std::string, std::string>> texts(const std::vector<Parameter>& params) const;
};

/// MeshLab filter classes used here (values of MeshFilterInterface::FilterClass / FilterPlugin).
enum class FilterKind { Quality, Selection, Smoothing, Measure };

/// What a filter needs from and changes in the mesh (bit flags; the API adapter maps them to
/// MeshLab's MeshModel masks).
enum MeshData : unsigned {
    kNothing = 0,
    kVertexQuality = 1,
    kVertexColor = 2,
    kVertexSelection = 4,
    kVertexCoordinates = 8,
    kNormals = 16,
    kTopology = 32,  ///< vertices or faces added or removed (a filter's "repair")
};

/// One filter: menu name (also the .mlx name), Python name, class, description, parameters, and
/// what it reads and changes; built with the constructor and named setters:
///   FilterSpec("Conformal factor", "compute_conformal_factor", FilterKind::Quality)
///       .with_info(...).with_params({...}).with_needs(kVertexQuality).with_changes(...)
struct FilterSpec {
    int id = 0;               ///< its index in its table (MeshLab's filter id; set by number_filters())
    std::string name;         ///< menu name, also the name in a .mlx script
    std::string python_name;  ///< pymeshlab's name
    FilterKind kind = FilterKind::Measure;
    std::string info;  ///< HTML description shown by MeshLab (with the citation)
    std::vector<Parameter> params;
    unsigned needs = kNothing;    ///< MeshData flags the mesh must have (not `requires`: a C++20 keyword)
    unsigned changes = kNothing;  ///< MeshData flags the filter changes

    FilterSpec(std::string menu_name, std::string python, FilterKind k)
        : name(std::move(menu_name)), python_name(std::move(python)), kind(k) {}
    FilterSpec& with_info(std::string html) {
        info = std::move(html);
        return *this;
    }
    FilterSpec& with_params(std::vector<Parameter> p) {
        params = std::move(p);
        return *this;
    }
    FilterSpec& with_needs(unsigned flags) {
        needs = flags;
        return *this;
    }
    FilterSpec& with_changes(unsigned flags) {
        changes = flags;
        return *this;
    }

    /// The shipped .mlx file: the menu name in lower case, spaces as '_' ("conformal_factor.mlx").
    std::string script_file() const;
};

/// Gives every filter of a table its index as id (a table's last step).
void number_filters(std::vector<FilterSpec>& table);

/// `a` followed by `b` (a filter's parameters from several definitions).
std::vector<Parameter> concat(std::vector<Parameter> a, const std::vector<Parameter>& b);

/// A parameter's default as MeshLab's dialog holds it: a switch 0/1, a number, an enum's index.
double default_number(const Parameter& p);
/// The tooltip of a filter parameter: its help as a sentence, with its range.
std::string tooltip(const Parameter& p);

/// The spec of filter `id` in `table`.
const FilterSpec& filter_spec(const std::vector<FilterSpec>& table, int id);
/// The spec of the filter whose Python name is `python_name` (std::logic_error if none).
const FilterSpec& filter_named(const std::vector<FilterSpec>& table, const std::string& python_name);

/// A filter description written as a paragraph in the table's source (a raw string over several
/// lines): every run of white space, line breaks and indentation included, becomes one space.
std::string prose(const char* text);

/// The first log line of every application of `spec`: "canonform VERSION: NAME", so that a
/// MeshLab log or a bug report names the plugin's version.
std::string log_header(const FilterSpec& spec);

/// A MeshLab filter script (.mlx) applying `spec` with every parameter at its default.
std::string default_script(const FilterSpec& spec);

}  // namespace canonform::meshlab
