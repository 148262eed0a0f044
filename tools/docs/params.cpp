// SPDX-License-Identifier: GPL-3.0-or-later
// Writes every filter of both plugins and every canonical-form method of the registry, with all
// their parameters, as JSON: `canonform_params [OUT.json]` (without OUT.json: on stdout). The documentation's filter
// and pymeshlab pages are generated from it (tools/docs/generate.py), so they say what the filter
// tables (filter_canonical/canonical_filter_table.cpp, filter_viewdescriptor/view_filter_table.cpp)
// and the method registry (src/canonform/canonical/method_registry.cpp) say, and nothing else.
#include "canonical_filter_table.h"
#include "view_filter_table.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/common/version.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

using canonform::meshlab::FilterKind;
using canonform::meshlab::FilterSpec;
using canonform::meshlab::ParamKind;
using nlohmann::ordered_json;

const char* kind_name(ParamKind k) {
    switch (k) {
    case ParamKind::Bool: return "bool";
    case ParamKind::Int: return "int";
    case ParamKind::Float: return "float";
    case ParamKind::Enum: return "enum";
    case ParamKind::String: return "string";
    }
    return "?";
}

/// The MeshLab menu a filter class appears in (MeshLab's own menu names).
const char* menu(FilterKind k) {
    switch (k) {
    case FilterKind::Quality:
    case FilterKind::Measure: return "Filters > Quality Measure and Computations";
    case FilterKind::Selection: return "Filters > Selection";
    case FilterKind::Smoothing: return "Filters > Smoothing, Fairing and Deformation";
    }
    return "?";
}

/// The registry's range of a parameter of that name (the family's methods first, then any method):
/// [min, max], or null where the registry states none.
ordered_json registry_range(const std::string& name, canonform::canonical::MethodFamily family) {
    const canonform::MethodParameter* found = nullptr;
    for (int pass = 0; pass < 2 && !found; ++pass)
        for (const auto& m : canonform::canonical::canonical_methods()) {
            if (pass == 0 && m.family != family) continue;
            if (const auto* p = m.parameter(name); p && (p->min != 0 || p->max != 0)) {
                found = p;
                break;
            }
        }
    if (!found) return nullptr;
    return ordered_json::array({found->min, found->max});
}

canonform::canonical::MethodFamily family_of(const FilterSpec& f) {
    const std::string py = f.python_name;
    if (py == "generate_geodesic_canonical_form") return canonform::canonical::MethodFamily::Geodesic;
    return canonform::canonical::MethodFamily::Euclidean;
}

ordered_json filters(const std::vector<FilterSpec>& table) {
    ordered_json out = ordered_json::array();
    for (const auto& f : table) {
        ordered_json params = ordered_json::array();
        for (const auto& p : f.params) {
            ordered_json j;
            j["name"] = p.name;
            j["type"] = kind_name(p.kind);
            switch (p.kind) {
            case ParamKind::Bool: j["default"] = p.default_value != 0; break;
            case ParamKind::Int: j["default"] = static_cast<long long>(p.default_value); break;
            case ParamKind::Float: j["default"] = p.default_value; break;
            case ParamKind::Enum: j["default"] = p.choices.at(static_cast<size_t>(p.default_value)); break;
            case ParamKind::String: j["default"] = p.default_text; break;
            }
            j["label"] = p.label;
            j["tooltip"] = p.tooltip;
            j["choices"] = p.choices;
            j["range"] = (p.kind == ParamKind::Int || p.kind == ParamKind::Float)
                             ? registry_range(p.name, family_of(f))
                             : ordered_json(nullptr);
            params.push_back(j);
        }
        out.push_back({{"name", f.name},
                       {"python_name", f.python_name},
                       {"script", f.script_file},
                       {"menu", menu(f.kind)},
                       {"info", f.info},
                       {"parameters", params}});
    }
    return out;
}

const char* family_name(canonform::canonical::MethodFamily f) {
    switch (f) {
    case canonform::canonical::MethodFamily::None: return "";
    case canonform::canonical::MethodFamily::Euclidean: return "Euclidean canonical form";
    case canonform::canonical::MethodFamily::Geodesic: return "Geodesic canonical form";
    }
    return "";
}

ordered_json methods() {
    ordered_json out = ordered_json::array();
    for (const auto& m : canonform::canonical::canonical_methods()) {
        ordered_json params = ordered_json::array();
        for (const auto& p : m.parameters) {
            ordered_json j;
            j["name"] = p.name;
            j["default"] = p.default_value;
            j["help"] = p.help;
            j["range"] = (p.min != 0 || p.max != 0) ? ordered_json::array({p.min, p.max}) : ordered_json(nullptr);
            j["integer"] = p.integer;
            j["choices"] = p.choices;
            j["alias"] = p.alias;
            j["affects_result"] = p.affects_result;
            params.push_back(j);
        }
        out.push_back({{"name", m.name},
                       {"label", m.label},
                       {"filter", family_name(m.family)},
                       {"help", m.help},
                       {"parameters", params}});
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc > 2) {
        std::cerr << "usage: canonform_params [OUT.json]\n";
        return 2;
    }
    ordered_json j;
    j["version"] = canonform::version();
    j["plugins"] = {{{"plugin", "filter_canonical"}, {"filters", filters(canonform::meshlab::filter_table())}},
                    {{"plugin", "filter_viewdescriptor"},
                     {"filters", filters(canonform::meshlab::view_filter_table())}}};
    j["methods"] = methods();
    if (argc == 2) {
        std::ofstream out(argv[1]);
        out << j.dump(1) << "\n";
        if (!out) {
            std::cerr << "canonform_params: cannot write " << argv[1] << "\n";
            return 1;
        }
        return 0;
    }
    std::cout << j.dump(1) << "\n";
    return 0;
}
