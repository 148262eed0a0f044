// canonform: the one table that describes the filters of the filter_canonical plugin.
//
// Names, classes, Python names and parameters live here, in plain C++ (no Qt, no MeshLab), so
// that every MeshLab API adapter (2020.09's MeshFilterInterface today, 2022.02's FilterPlugin
// next), the shipped .mlx scripts and the tests all read the same facts.
#pragma once

#include <string>
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

enum class ParamKind { Bool, Int, Float, Enum };

/// One filter parameter: its name, kind, default, dialog label and tooltip.
struct ParamSpec {
    const char* name;
    ParamKind kind;
    double default_value;             ///< bool: 0/1; enum: index
    const char* label;
    const char* tooltip;
    std::vector<std::string> choices; ///< enum only
};

/// MeshLab filter classes used here (values of MeshFilterInterface::FilterClass / FilterPlugin).
enum class FilterKind { Quality, Selection, Smoothing };

enum class FilterId : int {
    ConformalFactor = 0,
    FeaturePoints = 1,
    EuclideanCanonicalForm = 2,
    GeodesicCanonicalForm = 3,
};

/// One filter: menu name (also the .mlx name), Python name, class, description, parameters.
struct FilterSpec {
    FilterId id;
    const char* name;
    const char* python_name;
    const char* script_file;  ///< shipped .mlx file name
    FilterKind kind;
    std::string info;         ///< HTML description shown by MeshLab (with the citation)
    std::vector<ParamSpec> params;
};

/// The table of all filters of the plugin, in menu order.
const std::vector<FilterSpec>& filter_table();

/// The spec of one filter.
const FilterSpec& filter_spec(FilterId id);

/// A MeshLab filter script (.mlx) applying `spec` with every parameter at its default.
std::string default_script(const FilterSpec& spec);

}  // namespace canonform::plugin
