// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the types of a plugin's filter table, shared by both plugins and every MeshLab API
// adapter.
//
// A plugin describes its filters once, as a table of FilterSpec (names, classes, Python names,
// parameters, what a filter reads and changes) in plain C++ (no Qt, no MeshLab). Every MeshLab API
// adapter (meshlab2020_adapter for MeshFilterInterface, meshlab2022_adapter for FilterPlugin),
// the shipped .mlx scripts and the tests read the same table.
#pragma once

#include "canonform/common/errors.h"

#include <functional>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace canonform::meshlab {

enum class ParamKind { Bool, Int, Float, Enum, String };

/// One filter parameter: its name, kind, default, dialog label and tooltip.
struct ParamSpec {
    const char* name;
    ParamKind kind;
    double default_value;             ///< bool: 0/1; enum: index
    const char* label;
    const char* tooltip;
    std::vector<std::string> choices; ///< enum only
    std::string default_text = {};    ///< string only
};

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

/// Parameter values by name (bool: 0/1, enum: index; strings apart).
struct ParamValues {
    std::map<std::string, double> values;
    std::map<std::string, std::string> strings;
    double get(const char* name) const;
    int get_int(const char* name) const { return static_cast<int>(get(name)); }
    bool get_bool(const char* name) const { return get(name) != 0; }
    const std::string& get_string(const char* name) const;
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

/// One filter: menu name (also the .mlx name), Python name, class, description, parameters.
struct FilterSpec {
    int id;                   ///< unique within its plugin (the plugin's own id enum)
    const char* name;
    const char* python_name;
    const char* script_file;  ///< shipped .mlx file name
    FilterKind kind;
    std::string info;         ///< HTML description shown by MeshLab (with the citation)
    std::vector<ParamSpec> params;
    unsigned needs = kNothing;     ///< MeshData flags the mesh must have (not `requires`: a C++20 keyword)
    unsigned changes = kNothing;   ///< MeshData flags the filter changes
};

/// The spec of filter `id` in `table`.
const FilterSpec& filter_spec(const std::vector<FilterSpec>& table, int id);

/// A filter description written as a paragraph in the table's source (a raw string over several
/// lines): every run of white space, line breaks and indentation included, becomes one space.
std::string prose(const char* text);

/// The first log line of every application of `spec`: "canonform VERSION: NAME", so that a
/// MeshLab log or a bug report names the plugin's version.
std::string log_header(const FilterSpec& spec);

/// A MeshLab filter script (.mlx) applying `spec` with every parameter at its default.
std::string default_script(const FilterSpec& spec);

}  // namespace canonform::meshlab
