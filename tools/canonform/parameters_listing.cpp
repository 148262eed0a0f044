// canonform tool: `canonform --list-parameters [--json]` - every parameter definition
// (common/parameters.h) as the method registry, both plugins' filter tables and the tool's commands
// use it: the input of the documentation pages of methods, filters, pymeshlab keywords and command
// options (docs/extending.md says how).
#include "cli.h"

#include "canonical_filter_table.h"
#include "view_filter_table.h"

#include "canonform/canonical/method_registry.h"

#include <iostream>

namespace canonform::cli {

namespace {

using Json = nlohmann::ordered_json;

Json parameter_json(const Parameter& p) {
    Json j = {{"name", p.name()}, {"type", to_string(p.type())}, {"default", p.default_value()},
              {"label", p.label()}, {"help", p.help()}, {"requirement", p.requirement()}};
    if (p.is_number()) {
        j["min"] = p.min();
        j["max"] = p.max();
    }
    if (p.type() == ParameterType::Choice) j["choices"] = p.choices();
    if (p.zero_means_default()) j["zero_means_default"] = true;
    if (!p.affects_result()) j["affects_result"] = false;
    if (!p.alias().empty()) j["alias"] = p.alias();
    return j;
}

const char* family_name(MethodFamily f) {
    switch (f) {
    case MethodFamily::Euclidean: return "euclidean";
    case MethodFamily::Geodesic: return "geodesic";
    case MethodFamily::None: break;
    }
    return "";
}

const char* meshlab_type(ParameterType t) {
    switch (t) {
    case ParameterType::Bool: return "RichBool";
    case ParameterType::Int: return "RichInt";
    case ParameterType::Float: return "RichFloat";
    case ParameterType::Choice: return "RichEnum";
    case ParameterType::Text: return "RichString";
    }
    return "";
}

const char* filter_class(plugin::FilterKind k) {
    switch (k) {
    case plugin::FilterKind::Quality: return "Quality";
    case plugin::FilterKind::Selection: return "Selection";
    case plugin::FilterKind::Smoothing: return "Smoothing";
    case plugin::FilterKind::Measure: return "Measure";
    }
    return "";
}

Json filters_json(const char* plugin_name, const std::vector<plugin::FilterSpec>& table) {
    Json out = Json::array();
    for (const auto& f : table) {
        Json params = Json::array();
        for (const Parameter& p : f.params) {
            Json j = parameter_json(p);
            j["meshlab_type"] = meshlab_type(p.type());
            j["tooltip"] = plugin::tooltip(p);
            params.push_back(j);
        }
        out.push_back({{"plugin", plugin_name}, {"name", f.name}, {"python_name", f.python_name},
                       {"script", f.script_file()}, {"class", filter_class(f.kind)}, {"info", f.info},
                       {"parameters", params}});
    }
    return out;
}

Json commands_json(CLI::App& app) {
    Json out = Json::array();
    for (const CLI::App* c : app.get_subcommands({})) {
        Json options = Json::array();
        for (const CLI::Option* o : c->get_options()) {
            if (o->get_name() == "--help" || o->get_name() == "-h") continue;
            Json names = Json::array();
            for (const auto& n : o->get_lnames()) names.push_back("--" + n);
            for (const auto& n : o->get_snames()) names.push_back("-" + n);
            Json j = {{"names", names}, {"positional", o->get_positional()}, {"flag", o->get_expected_min() == 0},
                      {"required", o->get_required()}, {"help", o->get_description()},
                      {"type", o->get_type_name()}};
            if (!o->get_default_str().empty()) j["default"] = o->get_default_str();
            if (o->get_positional()) j["names"] = Json::array({o->get_name()});
            options.push_back(j);
        }
        out.push_back({{"command", c->get_name()}, {"help", c->get_description()}, {"options", options}});
    }
    return out;
}

}  // namespace

void print_parameter_listing(CLI::App& app, bool json) {
    Json methods = Json::array();
    for (const CanonicalMethod* m : canonical_methods()) {
        Json params = Json::array();
        for (const Parameter& p : m->parameters) params.push_back(parameter_json(p));
        methods.push_back({{"name", m->name}, {"label", m->label}, {"family", family_name(m->family)},
                           {"family_default", m->family_default}, {"help", m->help}, {"parameters", params}});
    }
    Json filters = filters_json("filter_canonical", plugin::filter_table());
    for (auto& f : filters_json("filter_viewdescriptor", plugin::view_filter_table())) filters.push_back(f);
    if (json) {
        print_json({{"methods", methods}, {"filters", filters}, {"commands", commands_json(app)}});
        return;
    }
    // Plain text: what a person scans.
    std::cout << "Methods (canonform canonical --method NAME, retrieve --method NAME[:KEY=VALUE...])\n";
    for (const auto& m : methods) {
        std::cout << "  " << m["name"].get<std::string>() << ": " << m["help"].get<std::string>() << "\n";
        for (const auto& p : m["parameters"])
            std::cout << "    " << p["name"].get<std::string>() << " = " << p["default"].get<std::string>() << "  ("
                      << p["requirement"].get<std::string>() << ") " << p["help"].get<std::string>() << "\n";
    }
    std::cout << "\nMeshLab filters (pymeshlab: ms.PYTHON_NAME(KEYWORD=VALUE, ...))\n";
    for (const auto& f : filters) {
        std::cout << "  " << f["name"].get<std::string>() << " (" << f["python_name"].get<std::string>() << ", "
                  << f["plugin"].get<std::string>() << ")\n";
        for (const auto& p : f["parameters"])
            std::cout << "    " << p["name"].get<std::string>() << " = " << p["default"].get<std::string>() << "  ["
                      << p["meshlab_type"].get<std::string>() << "] " << p["tooltip"].get<std::string>() << "\n";
    }
}

}  // namespace canonform::cli
