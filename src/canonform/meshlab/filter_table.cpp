// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/meshlab/filter_table.h"

#include "canonform/common/version.h"

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace canonform::meshlab {

namespace {

std::string xml_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
        case '&': o += "&amp;"; break;
        case '<': o += "&lt;"; break;
        case '>': o += "&gt;"; break;
        case '"': o += "&quot;"; break;
        default: o += c;
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

double ParamValues::get(const char* name) const {
    const auto it = values.find(name);
    if (it == values.end()) throw std::invalid_argument(std::string("missing filter parameter '") + name + "'");
    return it->second;
}

const std::string& ParamValues::get_string(const char* name) const {
    const auto it = strings.find(name);
    if (it == strings.end()) throw std::invalid_argument(std::string("missing filter parameter '") + name + "'");
    return it->second;
}

std::string default_script(const FilterSpec& spec) {
    std::ostringstream o;
    o << "<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name=\"" << xml_escape(spec.name) << "\">\n";
    for (const auto& p : spec.params) {
        o << "  <Param name=\"" << p.name << "\"";
        switch (p.kind) {
        case ParamKind::Bool: o << " type=\"RichBool\" value=\"" << (p.default_value != 0 ? "true" : "false") << "\""; break;
        case ParamKind::Int: o << " type=\"RichInt\" value=\"" << static_cast<long>(p.default_value) << "\""; break;
        case ParamKind::Float: {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%g", p.default_value);
            o << " type=\"RichFloat\" value=\"" << buf << "\"";
            break;
        }
        case ParamKind::String:
            o << " type=\"RichString\" value=\"" << xml_escape(p.default_text) << "\"";
            break;
        case ParamKind::Enum:
            o << " type=\"RichEnum\" value=\"" << static_cast<long>(p.default_value) << "\" enum_cardinality=\""
              << p.choices.size() << "\"";
            for (size_t k = 0; k < p.choices.size(); ++k)
                o << " enum_val" << k << "=\"" << xml_escape(p.choices[k]) << "\"";
            break;
        }
        o << " description=\"" << xml_escape(p.label) << "\" tooltip=\"" << xml_escape(p.tooltip) << "\"/>\n";
    }
    o << " </filter>\n</FilterScript>\n";
    return o.str();
}

}  // namespace canonform::meshlab
