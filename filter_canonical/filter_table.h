// canonform: the one table that describes the filters of the filter_canonical plugin.
//
// Names, classes, Python names and parameters live here, in plain C++ (no Qt, no MeshLab), so
// that every MeshLab API adapter (2020.09's MeshFilterInterface today, 2022.02's FilterPlugin
// next), the shipped .mlx scripts and the tests all read the same facts.
#pragma once

#include "core/errors.h"

#include <functional>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace canonform::plugin {

/// Parameter names: lower snake_case (pymeshlab derives its Python keyword names from them).
namespace param {
inline constexpr const char* normalize = "normalize";
inline constexpr const char* colorize = "colorize";
inline constexpr const char* ring = "ring";
inline constexpr const char* fill = "fill";
inline constexpr const char* seed = "seed";
inline constexpr const char* add_layer = "add_layer";
inline constexpr const char* variant = "variant";
inline constexpr const char* alpha = "alpha";
inline constexpr const char* beta = "beta";
inline constexpr const char* tolerance = "tolerance";
inline constexpr const char* max_iterations = "max_iterations";
inline constexpr const char* new_layer = "new_layer";
inline constexpr const char* method = "method";
inline constexpr const char* max_memory_gib = "max_memory_gib";
inline constexpr const char* max_seconds = "max_seconds";
}  // namespace param

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
};

enum class FilterId : int {
    ConformalFactor = 0,
    FeaturePoints = 1,
    EuclideanCanonicalForm = 2,
    GeodesicCanonicalForm = 3,
};

/// One filter: menu name (also the .mlx name), Python name, class, description, parameters.
struct FilterSpec {
    int id;                   ///< unique within its plugin (FilterId for filter_canonical)
    const char* name;
    const char* python_name;
    const char* script_file;  ///< shipped .mlx file name
    FilterKind kind;
    std::string info;         ///< HTML description shown by MeshLab (with the citation)
    std::vector<ParamSpec> params;
    unsigned requires = kNothing;  ///< MeshData flags the mesh must have
    unsigned changes = kNothing;   ///< MeshData flags the filter changes
};

/// The table of all filters of filter_canonical, in menu order.
const std::vector<FilterSpec>& filter_table();

/// The spec of filter `id` in `table`.
const FilterSpec& filter_spec(const std::vector<FilterSpec>& table, int id);

/// A MeshLab filter script (.mlx) applying `spec` with every parameter at its default.
std::string default_script(const FilterSpec& spec);

}  // namespace canonform::plugin
