// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/meshlab/filter_table.h"

#include "canonform/common/version.h"

#include <cctype>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace canonform::meshlab {

namespace {

std::string xml_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
            case '&':
                o += "&amp;";
                break;
            case '<':
                o += "&lt;";
                break;
            case '>':
                o += "&gt;";
                break;
            case '"':
                o += "&quot;";
                break;
            default:
                o += c;
        }
    }
    return o;
}

}  // namespace

std::string prose(const char* text) {
    std::string out;
    bool space = false;
    for (const char* c = text; *c; ++c) {
        const bool white = *c == ' ' || *c == '\n' || *c == '\t' || *c == '\r';
        if (white) {
            space = !out.empty();
            continue;
        }
        if (space) out += ' ';
        space = false;
        out += *c;
    }
    return out;
}

std::string log_header(const FilterSpec& spec) {
    return std::string("canonform ") + version() + ": " + spec.name;
}

const FilterSpec& filter_spec(const std::vector<FilterSpec>& table, int id) {
    for (const auto& f : table)
        if (f.id == id) return f;
    throw std::logic_error("unknown filter id");
}

const FilterSpec& filter_named(const std::vector<FilterSpec>& table, const std::string& python_name) {
    for (const auto& f : table)
        if (f.python_name == python_name) return f;
    throw std::logic_error("no filter '" + python_name + "'");
}

std::string FilterSpec::script_file() const {
    std::string s;
    for (char c : name) s += c == ' ' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s + ".mlx";
}

void number_filters(std::vector<FilterSpec>& table) {
    for (size_t k = 0; k < table.size(); ++k) table[k].id = static_cast<int>(k);
}

std::vector<Parameter> concat(std::vector<Parameter> a, const std::vector<Parameter>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

double default_number(const Parameter& p) {
    switch (p.type()) {
        case ParameterType::Bool:
            return p.truth(p.default_value()) ? 1 : 0;
        case ParameterType::Int:
        case ParameterType::Float:
            return p.number(p.default_value());
        case ParameterType::Choice:
            return p.choice_index(p.default_value());
        case ParameterType::Text:
            return 0;
    }
    return 0;
}

std::string tooltip(const Parameter& p) {
    return p.sentence();
}

double ParamValues::get(const std::string& name) const {
    const auto it = values.find(name);
    if (it == values.end()) throw std::invalid_argument("missing filter parameter '" + name + "'");
    return it->second;
}

const std::string& ParamValues::get_string(const std::string& name) const {
    const auto it = strings.find(name);
    if (it == strings.end()) throw std::invalid_argument("missing filter parameter '" + name + "'");
    return it->second;
}

std::vector<std::pair<std::string, std::string>> ParamValues::texts(
    const std::vector<Parameter>& params) const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Parameter& p : params) {
        if (p.type() == ParameterType::Text) {
            if (strings.count(p.name())) out.emplace_back(p.name(), get_string(p.name()));
            continue;
        }
        if (!values.count(p.name())) continue;  // a script written before the parameter existed: its default
        const double v = get(p.name());
        std::ostringstream t;
        t.precision(17);
        switch (p.type()) {
            case ParameterType::Bool:
                t << (v != 0 ? "true" : "false");
                break;
            case ParameterType::Choice: {
                const int k = static_cast<int>(v);
                if (k < 0 || k >= static_cast<int>(p.choices().size()))
                    throw InputError(p.name() + " must be " + p.requirement() + ", got the index " +
                                     std::to_string(k));
                t << p.choices()[static_cast<size_t>(k)];
                break;
            }
            default:
                t << v;
        }
        out.emplace_back(p.name(), t.str());
    }
    return out;
}

std::string default_script(const FilterSpec& spec) {
    std::ostringstream o;
    o << "<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name=\"" << xml_escape(spec.name) << "\">\n";
    for (const auto& p : spec.params) {
        o << "  <Param name=\"" << p.name() << "\"";
        switch (p.type()) {
            case ParameterType::Bool:
                o << " type=\"RichBool\" value=\"" << (default_number(p) != 0 ? "true" : "false") << "\"";
                break;
            case ParameterType::Int:
                o << " type=\"RichInt\" value=\"" << static_cast<long>(default_number(p)) << "\"";
                break;
            case ParameterType::Float: {
                char buf[64];
                std::snprintf(buf, sizeof buf, "%g", default_number(p));
                o << " type=\"RichFloat\" value=\"" << buf << "\"";
                break;
            }
            case ParameterType::Text:
                o << " type=\"RichString\" value=\"" << xml_escape(p.default_value()) << "\"";
                break;
            case ParameterType::Choice:
                o << " type=\"RichEnum\" value=\"" << static_cast<long>(default_number(p))
                  << "\" enum_cardinality=\"" << p.choices().size() << "\"";
                for (size_t k = 0; k < p.choices().size(); ++k)
                    o << " enum_val" << k << "=\"" << xml_escape(p.choices()[k]) << "\"";
                break;
        }
        o << " description=\"" << xml_escape(p.label()) << "\" tooltip=\"" << xml_escape(tooltip(p))
          << "\"/>\n";
    }
    o << " </filter>\n</FilterScript>\n";
    return o.str();
}

}  // namespace canonform::meshlab
