// SPDX-License-Identifier: GPL-3.0-or-later
// Writes every filter of both plugins and every canonical-form method of the registry, with all
// their parameters, and the indexed query's defaults (collection_index.h), as JSON:
// `canonform_params [OUT.json]` (without OUT.json: on stdout). The documentation's
// filter and pymeshlab pages are generated from it (tools/docs/generate.py), so they say what the filter
// tables (filter_canonical/canonical_filter_table.cpp, filter_viewdescriptor/view_filter_table.cpp)
// and the method registry (src/canonform/canonical/method_registry.cpp) say, and nothing else.
#include "canonical_filter_table.h"
#include "view_filter_table.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/common/version.h"
#include "canonform/retrieval/collection_index.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

using canonform::Parameter;
using canonform::ParameterType;
using canonform::meshlab::FilterKind;
using canonform::meshlab::FilterSpec;
using nlohmann::ordered_json;

/// The parameter types as the generator names them.
const char* kind_name(ParameterType t) {
    switch (t) {
        case ParameterType::Bool:
            return "bool";
        case ParameterType::Int:
            return "int";
        case ParameterType::Float:
            return "float";
        case ParameterType::Choice:
            return "enum";
        case ParameterType::Text:
            return "string";
    }
    return "?";
}

/// The MeshLab menu a filter class appears in (MeshLab's own menu names).
const char* menu(FilterKind k) {
    switch (k) {
        case FilterKind::Quality:
        case FilterKind::Measure:
            return "Filters > Quality Measure and Computations";
        case FilterKind::Selection:
            return "Filters > Selection";
        case FilterKind::Smoothing:
            return "Filters > Smoothing, Fairing and Deformation";
    }
    return "?";
}

/// [min, max] of a number, null otherwise (every number has its range in its definition).
ordered_json range(const Parameter& p) {
    return p.is_number() ? ordered_json::array({p.min(), p.max()}) : ordered_json(nullptr);
}

ordered_json filters(const std::vector<FilterSpec>& table) {
    ordered_json out = ordered_json::array();
    for (const auto& f : table) {
        ordered_json params = ordered_json::array();
        for (const Parameter& p : f.params) {
            ordered_json j;
            j["name"] = p.name();
            j["type"] = kind_name(p.type());
            switch (p.type()) {
                case ParameterType::Bool:
                    j["default"] = canonform::meshlab::default_number(p) != 0;
                    break;
                case ParameterType::Int:
                    j["default"] = static_cast<long long>(canonform::meshlab::default_number(p));
                    break;
                case ParameterType::Float:
                    j["default"] = canonform::meshlab::default_number(p);
                    break;
                case ParameterType::Choice:
                case ParameterType::Text:
                    j["default"] = p.default_value();
                    break;
            }
            j["label"] = p.label();
            j["tooltip"] = canonform::meshlab::tooltip(p);
            j["choices"] = p.choices();
            j["range"] = range(p);
            params.push_back(j);
        }
        out.push_back({{"name", f.name},
                       {"python_name", f.python_name},
                       {"script", f.script_file()},
                       {"menu", menu(f.kind)},
                       {"info", f.info},
                       {"parameters", params}});
    }
    return out;
}

const char* family_name(canonform::canonical::MethodFamily f) {
    switch (f) {
        case canonform::canonical::MethodFamily::None:
            return "";
        case canonform::canonical::MethodFamily::Euclidean:
            return "Euclidean canonical form";
        case canonform::canonical::MethodFamily::Geodesic:
            return "Geodesic canonical form";
    }
    return "";
}

ordered_json methods() {
    ordered_json out = ordered_json::array();
    for (const canonform::canonical::CanonicalMethod* m : canonform::canonical::canonical_methods()) {
        ordered_json params = ordered_json::array();
        for (const Parameter& p : m->parameters) {
            ordered_json j;
            j["name"] = p.name();
            j["default"] = p.default_value();
            j["help"] = p.help();
            j["range"] = range(p);
            j["integer"] = p.type() == ParameterType::Int;
            j["choices"] = p.choices();
            j["alias"] = p.alias();
            j["affects_result"] = p.affects_result();
            params.push_back(j);
        }
        out.push_back({{"name", m->name},
                       {"label", m->label},
                       {"filter", family_name(m->family)},
                       {"help", m->help},
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
    j["plugins"] = {
        {{"plugin", "filter_canonical"}, {"filters", filters(canonform::meshlab::filter_table())}},
        {{"plugin", "filter_viewdescriptor"}, {"filters", filters(canonform::meshlab::view_filter_table())}}};
    j["methods"] = methods();
    using canonform::retrieval::CollectionIndex;
    j["query"] = {{"two_stage_above", CollectionIndex::kTwoStageAbove},
                  {"candidates_min", CollectionIndex::kCandidatesMin},
                  {"candidates_per_k", CollectionIndex::kCandidatesPerK},
                  {"candidates_share", CollectionIndex::kCandidatesShare},
                  {"candidates_rule", CollectionIndex::default_candidates_rule()},
                  {"code_bytes", canonform::retrieval::SummaryOptions{}.dims}};
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
