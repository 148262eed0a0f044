// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/common/parameters.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace canonform {

namespace {

std::string join(const std::vector<std::string>& items, const char* separator) {
    std::string s;
    for (const auto& item : items) s += (s.empty() ? "" : separator) + item;
    return s;
}

/// Parses all of `text` as a number (no leading or trailing characters, not empty).
bool parse_number(const std::string& text, double* value) {
    if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
    char* end = nullptr;
    *value = std::strtod(text.c_str(), &end);
    return end != nullptr && *end == '\0';
}

}  // namespace

const char* to_string(ParameterType type) {
    switch (type) {
        case ParameterType::Bool:
            return "bool";
        case ParameterType::Int:
            return "int";
        case ParameterType::Float:
            return "float";
        case ParameterType::Choice:
            return "choice";
        case ParameterType::Text:
            return "text";
    }
    return "?";
}

std::string format_number(double value) {
    char buf[64];
    int digits = 1;
    for (; digits < 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, value);
        if (std::strtod(buf, nullptr) == value) break;
    }
    // Plain digits for ordinary magnitudes and for every number written to its units (130,
    // 2147483647), an exponent for very small and round large ones (1e-5, 1e6).
    if (value != 0 && std::isfinite(value)) {
        const int e = static_cast<int>(std::floor(std::log10(std::fabs(value))));
        if ((e > -5 && e < 6) || digits > e)
            std::snprintf(buf, sizeof buf, "%.*g", std::max(digits, e + 1), value);
    }
    std::string s = buf;
    // "1e-05" -> "1e-5", "1e+06" -> "1e6": as a person writes it.
    const auto e = s.find('e');
    if (e != std::string::npos) {
        std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
        const bool negative = !exponent.empty() && exponent[0] == '-';
        if (!exponent.empty() && (exponent[0] == '-' || exponent[0] == '+')) exponent.erase(0, 1);
        while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
        s = mantissa + "e" + (negative ? "-" : "") + exponent;
    }
    return s;
}

Parameter::Parameter(std::string name, ParameterType type) : name_(std::move(name)), type_(type) {
    // The label until one is given: "max_seconds" -> "Max seconds".
    label_ = name_;
    for (char& c : label_)
        if (c == '_') c = ' ';
    if (!label_.empty()) label_[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(label_[0])));
}

Parameter Parameter::flag(std::string name) {
    Parameter p(std::move(name), ParameterType::Bool);
    p.default_ = "false";
    return p;
}

Parameter Parameter::integer(std::string name, double min, double max) {
    Parameter p(std::move(name), ParameterType::Int);
    p.min_ = min;
    p.max_ = max;
    p.default_ = format_number(min);
    return p;
}

Parameter Parameter::number(std::string name, double min, double max) {
    Parameter p(std::move(name), ParameterType::Float);
    p.min_ = min;
    p.max_ = max;
    p.default_ = format_number(min);
    return p;
}

Parameter Parameter::choice(std::string name, std::vector<std::string> choices) {
    Parameter p(std::move(name), ParameterType::Choice);
    p.choices_ = std::move(choices);
    if (!p.choices_.empty()) p.default_ = p.choices_.front();
    return p;
}

Parameter Parameter::text(std::string name) {
    return Parameter(std::move(name), ParameterType::Text);
}

Parameter& Parameter::label(std::string text) {
    label_ = std::move(text);
    return *this;
}

Parameter& Parameter::help(std::string text) {
    help_ = std::move(text);
    return *this;
}

Parameter& Parameter::default_value(std::string text) {
    default_ = std::move(text);
    return *this;
}

Parameter& Parameter::zero_means_default(bool on) {
    zero_means_default_ = on;
    return *this;
}

Parameter& Parameter::affects_result(bool on) {
    affects_result_ = on;
    return *this;
}

Parameter& Parameter::alias(std::string name) {
    alias_ = std::move(name);
    return *this;
}

std::string Parameter::requirement() const {
    switch (type_) {
        case ParameterType::Bool:
            return "true or false";
        case ParameterType::Text:
            return "a text";
        case ParameterType::Choice:
            return "one of " + join(choices_, ", ");
        case ParameterType::Int:
        case ParameterType::Float:
            if (zero_means_default_) return "a positive number (or 0 for the default)";
            return std::string(type_ == ParameterType::Int ? "a whole number" : "a finite number") +
                   " between " + format_number(min_) + " and " + format_number(max_);
    }
    return "";
}

void Parameter::check(const std::string& value) const {
    switch (type_) {
        case ParameterType::Text:
            return;
        case ParameterType::Bool:
            if (value == "true" || value == "false") return;
            break;
        case ParameterType::Choice:
            if (std::find(choices_.begin(), choices_.end(), value) != choices_.end()) return;
            break;
        case ParameterType::Int:
        case ParameterType::Float: {
            double v = 0;
            if (parse_number(value, &v) && std::isfinite(v) &&
                (type_ != ParameterType::Int || v == std::floor(v)) &&
                ((v >= min_ && v <= max_) || (zero_means_default_ && v == 0)))
                return;
            break;
        }
    }
    throw InputError(name_ + " must be " + requirement() + ", got '" + value + "'");
}

double Parameter::number(const std::string& value) const {
    double v = 0;
    if (!parse_number(value, &v) || !std::isfinite(v))
        throw InputError(name_ + " must be " + requirement() + ", got '" + value + "'");
    return v;
}

bool Parameter::truth(const std::string& value) const {
    if (value == "true") return true;
    if (value == "false") return false;
    throw InputError(name_ + " must be true or false, got '" + value + "'");
}

int Parameter::choice_index(const std::string& value) const {
    for (std::size_t k = 0; k < choices_.size(); ++k)
        if (choices_[k] == value) return static_cast<int>(k);
    throw InputError(name_ + " must be " + requirement() + ", got '" + value + "'");
}

std::string Parameter::sentence() const {
    std::string s = help_;
    if (is_number()) s += (s.empty() ? "(" : " (") + format_number(min_) + " to " + format_number(max_) + ")";
    if (!s.empty() && s.back() != '.') s += '.';
    return s;
}

const Parameter* find_parameter(const std::vector<Parameter>& list, const std::string& name) {
    for (const Parameter& p : list)
        if (p.name() == name) return &p;
    return nullptr;
}

Settings::Settings(const std::vector<Parameter>& parameters,
                   const std::vector<std::pair<std::string, std::string>>& given) {
    for (const Parameter& p : parameters) values_[p.name()] = p.default_value();
    for (const auto& [name, value] : given) {
        const Parameter* p = find_parameter(parameters, name);
        if (!p) {
            std::vector<std::string> names;
            for (const Parameter& q : parameters) names.push_back(q.name());
            throw InputError("unknown parameter '" + name + "' (" +
                             (names.empty() ? "none" : join(names, ", ")) + ")");
        }
        p->check(value);
        if (p->zero_means_default() && p->number(value) == 0) continue;  // 0 stands for the default
        values_[name] = value;
    }
}

const std::string& Settings::text(const std::string& name) const {
    const auto it = values_.find(name);
    if (it == values_.end()) throw std::logic_error("parameter '" + name + "' not set");
    return it->second;
}

double Settings::number(const std::string& name) const {
    const std::string& t = text(name);
    double v = 0;
    if (!parse_number(t, &v) || !std::isfinite(v))
        throw InputError("parameter " + name + ": '" + t + "' is not a finite number");
    return v;
}

int Settings::integer(const std::string& name) const {
    const double v = number(name);
    if (v != std::floor(v) || v < -2147483648.0 || v > 2147483647.0)
        throw InputError("parameter " + name + ": '" + text(name) + "' is not a whole number in int's range");
    return static_cast<int>(v);
}

bool Settings::flag(const std::string& name) const {
    const std::string& t = text(name);
    if (t == "true") return true;
    if (t == "false") return false;
    throw InputError("parameter " + name + ": '" + t + "' is not true or false");
}

}  // namespace canonform
