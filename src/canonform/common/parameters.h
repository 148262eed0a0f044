// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the one definition of every parameter a user sets, and its binding to an options
// struct.
//
// A Parameter is a name, a type, a default, a range or a list of choices, a dialog label and a
// help text. Each algorithm defines its parameters once, next to its options struct, as a
// ParameterSet bound to the struct's members (euclidean_canonical_form_parameters(), ...): the
// default of a parameter is the member's default in the struct, never written a second time.
// Everything a user sees is derived from these definitions: the method registry
// (canonical/method_registry.h), the MeshLab filter tables and their .mlx scripts
// (meshlab/filter_table.h), the command-line options of the canonform tool, the pymeshlab
// harness's expected keywords and the parameter listing the documentation is generated from
// (`canonform --list-parameters --json`; docs/extending.md).
//
// Values travel as text ("10", "rre", "true"): on a command line, in a method spec
// ("euclidean-N:beta=65"), in a run's cache key. Settings holds the texts of one run, checked;
// ParameterSet::read() turns them into the options struct.
#pragma once

#include "canonform/common/errors.h"

#include <algorithm>
#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace canonform {

/// The type of a parameter's value. MeshLab shows them as RichBool, RichInt, RichFloat, RichEnum
/// and RichString; the tool as a flag, an integer, a number, one of a list and a text.
enum class ParameterType { Bool, Int, Float, Choice, Text };

/// "bool", "int", "float", "choice", "text" (the parameter listing's names).
const char* to_string(ParameterType type);

/// The shortest text that reads back as exactly `value` ("10", "1e-5", "0.25", "4294967295").
std::string format_number(double value);

/// One user-settable parameter: built with a kind (flag(), integer(), number(), choice(),
/// text()) and named setters, read with the getters of the same names.
///   Parameter::integer("ring", 1, 10).label("Ring size (k)").help("k of the k-ring ...")
class Parameter {
public:
    /// A switch ("true" or "false").
    static Parameter flag(std::string name);
    /// A whole number in [min, max].
    static Parameter integer(std::string name, double min, double max);
    /// A finite real number in [min, max].
    static Parameter number(std::string name, double min, double max);
    /// One of `choices` (by name; MeshLab's enum lists them in this order).
    static Parameter choice(std::string name, std::vector<std::string> choices);
    /// Free text (a file or folder name).
    static Parameter text(std::string name);

    // Named setters; each returns the parameter.
    Parameter& label(std::string text);          ///< dialog label (MeshLab); default: the name, capitalised
    Parameter& help(std::string text);           ///< what it does, a phrase without a final full stop
    Parameter& default_value(std::string text);  ///< as text; a ParameterSet sets it from its defaults
    Parameter& zero_means_default(bool on = true);  ///< numbers: a given 0 stands for the default
    Parameter& affects_result(bool on);             ///< false: not part of a retrieval run's cache key
    Parameter& alias(std::string name);             ///< a second, older tool option name ("tol"); for a
                                         ///< switch that is on by default, the one that turns it off

    // Getters.
    const std::string& name() const { return name_; }
    ParameterType type() const { return type_; }
    const std::string& label() const { return label_; }
    const std::string& help() const { return help_; }
    const std::string& default_value() const { return default_; }
    double min() const { return min_; }
    double max() const { return max_; }
    const std::vector<std::string>& choices() const { return choices_; }
    bool zero_means_default() const { return zero_means_default_; }
    bool affects_result() const { return affects_result_; }
    const std::string& alias() const { return alias_; }
    bool is_number() const { return type_ == ParameterType::Int || type_ == ParameterType::Float; }

    /// Checks `value` (InputError naming the parameter, the value and what it must be).
    void check(const std::string& value) const;
    /// What a value must be: "a whole number from 1 to 10", "one of none, random", ...
    std::string requirement() const;
    /// `value` as a number (InputError naming the parameter and the text unless it is one).
    double number(const std::string& value) const;
    /// `value` as a switch (InputError unless "true" or "false").
    bool truth(const std::string& value) const;
    /// The index of `value` among the choices (InputError naming them otherwise).
    int choice_index(const std::string& value) const;
    /// The help as one or two sentences, with what a value must be: a tooltip, a docs entry.
    std::string sentence() const;

private:
    Parameter(std::string name, ParameterType type);
    std::string name_;
    ParameterType type_ = ParameterType::Float;
    std::string label_, help_, default_;
    double min_ = 0, max_ = 0;
    std::vector<std::string> choices_;
    bool zero_means_default_ = false;
    bool affects_result_ = true;
    std::string alias_;
};

/// The parameter called `name` in `list`, or null.
const Parameter* find_parameter(const std::vector<Parameter>& list, const std::string& name);

/// The values of one run, as text, by parameter name: every parameter of a list at its default,
/// then the given values on top, each checked by its parameter.
class Settings {
public:
    Settings() = default;
    /// Every parameter of `parameters` at its default, then `given` (checked; InputError naming an
    /// unknown name or a bad value). A given 0 of a zero_means_default parameter keeps the default.
    Settings(const std::vector<Parameter>& parameters,
             const std::vector<std::pair<std::string, std::string>>& given);
    /// The texts as they are (no checks; for a caller that has them from a Settings).
    explicit Settings(std::map<std::string, std::string> values) : values_(std::move(values)) {}

    /// The value of `name` as a number, whole number or switch: InputError naming the parameter
    /// and the text if it is not one.
    double number(const std::string& name) const;
    int integer(const std::string& name) const;
    bool flag(const std::string& name) const;
    /// The text of `name` (std::logic_error if there is no such parameter: a programming error).
    const std::string& text(const std::string& name) const;
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    const std::map<std::string, std::string>& values() const { return values_; }

private:
    std::map<std::string, std::string> values_;
};

/// Parameters bound to the members of an options struct: their defaults are the members' values
/// in `defaults`, and read() writes a run's settings into a copy of `defaults`.
///   ParameterSet<FeaturePointOptions> s;
///   s.add(Parameter::integer("ring", 1, 10).help("..."), &FeaturePointOptions::ring);
/// A member's type fixes the parameter's: bool - Bool, an integer - Int, a floating-point number
/// - Float, an enum - Choice (the choices name the enumerators in their order), std::string - Text.
template <class Options>
class ParameterSet {
public:
    explicit ParameterSet(Options defaults = Options()) : defaults_(std::move(defaults)) {}

    /// Adds `p` bound to the member `get(options)` (a member pointer, or a callable returning a
    /// reference to a member of the options it is given).
    template <class Get>
    ParameterSet& add(Parameter p, Get get);

    /// Adds the parameters of `inner` (all, or those named in `only`) bound to the member
    /// `get(options)` of type Inner: their defaults become that member's values in this set's
    /// defaults.
    template <class Inner, class Get>
    ParameterSet& include(const ParameterSet<Inner>& inner, Get get,
                          const std::vector<std::string>& only = {});

    /// The parameters, in the order added (a copy from a temporary set, so that
    /// `for (const Parameter& p : some_parameters().parameters())` is safe).
    const std::vector<Parameter>& parameters() const& { return parameters_; }
    std::vector<Parameter> parameters() && { return std::move(parameters_); }
    /// The parameter `name`, to adjust it (std::logic_error if there is none).
    Parameter& parameter(const std::string& name);
    /// The defaults the parameters were bound with.
    const Options& defaults() const { return defaults_; }
    /// The defaults with every parameter of `settings` written in (settings from Settings(
    /// parameters(), given): every value present and checked).
    Options read(const Settings& settings) const;
    /// read() of the defaults and `given` (InputError on an unknown name or a bad value).
    Options read(const std::vector<std::pair<std::string, std::string>>& given) const {
        return read(Settings(parameters_, given));
    }

private:
    template <class>
    friend class ParameterSet;
    struct Binding {
        std::function<std::string(Options&)> text_of;         // the member's value as text
        std::function<void(Options&, const Settings&)> read;  // writes the setting in
    };
    Options defaults_;
    std::vector<Parameter> parameters_;
    std::vector<Binding> bindings_;
};

// --- implementation ------------------------------------------------------------------------------

namespace detail {

/// The member `get` names in `o`: a member pointer or a callable.
template <class Options, class Get>
decltype(auto) member_of(Options& o, const Get& get) {
    if constexpr (std::is_member_object_pointer_v<Get>)
        return (o.*get);
    else
        return get(o);
}

/// The ParameterType a member of type T takes.
template <class T>
constexpr ParameterType parameter_type_of() {
    if constexpr (std::is_same_v<T, bool>)
        return ParameterType::Bool;
    else if constexpr (std::is_enum_v<T>)
        return ParameterType::Choice;
    else if constexpr (std::is_integral_v<T>)
        return ParameterType::Int;
    else if constexpr (std::is_floating_point_v<T>)
        return ParameterType::Float;
    else {
        static_assert(std::is_same_v<T, std::string>,
                      "a parameter binds a bool, number, enum or string member");
        return ParameterType::Text;
    }
}

/// A member's value as the parameter's text.
template <class T>
std::string text_of_value(const Parameter& p, const T& v) {
    if constexpr (std::is_same_v<T, bool>)
        return v ? "true" : "false";
    else if constexpr (std::is_enum_v<T>) {
        const auto k = static_cast<std::size_t>(v);
        if (k >= p.choices().size())
            throw std::logic_error("parameter '" + p.name() + "': enumerator without a choice");
        return p.choices()[k];
    } else if constexpr (std::is_integral_v<T>)
        return std::to_string(v);
    else if constexpr (std::is_floating_point_v<T>)
        return format_number(static_cast<double>(v));
    else
        return v;
}

/// The setting `name` of `s` as a member of type T.
template <class T>
T value_of_setting(const Parameter& p, const Settings& s) {
    const std::string& text = s.text(p.name());
    if constexpr (std::is_same_v<T, bool>)
        return p.truth(text);
    else if constexpr (std::is_enum_v<T>)
        return static_cast<T>(p.choice_index(text));
    else if constexpr (std::is_integral_v<T>)
        return static_cast<T>(p.number(text));  // whole and in range: Parameter::check
    else if constexpr (std::is_floating_point_v<T>)
        return static_cast<T>(p.number(text));
    else
        return text;
}

}  // namespace detail

template <class Options>
template <class Get>
ParameterSet<Options>& ParameterSet<Options>::add(Parameter p, Get get) {
    using T = std::decay_t<decltype(detail::member_of(defaults_, get))>;
    if (p.type() != detail::parameter_type_of<T>())
        throw std::logic_error("parameter '" + p.name() + "' is bound to a member of another type");
    for (const Parameter& q : parameters_)
        if (q.name() == p.name()) throw std::logic_error("parameter '" + p.name() + "' added twice");
    p.default_value(detail::text_of_value(p, detail::member_of(defaults_, get)));
    p.check(p.default_value());
    const Parameter bound = p;
    bindings_.push_back(
        {[bound, get](Options& o) { return detail::text_of_value(bound, detail::member_of(o, get)); },
         [bound, get](Options& o, const Settings& s) {
             detail::member_of(o, get) = detail::value_of_setting<T>(bound, s);
         }});
    parameters_.push_back(std::move(p));
    return *this;
}

template <class Options>
template <class Inner, class Get>
ParameterSet<Options>& ParameterSet<Options>::include(const ParameterSet<Inner>& inner, Get get,
                                                      const std::vector<std::string>& only) {
    for (std::size_t k = 0; k < inner.parameters_.size(); ++k) {
        Parameter p = inner.parameters_[k];
        if (!only.empty() && std::find(only.begin(), only.end(), p.name()) == only.end()) continue;
        for (const Parameter& q : parameters_)
            if (q.name() == p.name()) throw std::logic_error("parameter '" + p.name() + "' added twice");
        const typename ParameterSet<Inner>::Binding b = inner.bindings_[k];
        p.default_value(b.text_of(detail::member_of(defaults_, get)));
        bindings_.push_back(
            {[b, get](Options& o) { return b.text_of(detail::member_of(o, get)); },
             [b, get](Options& o, const Settings& s) { b.read(detail::member_of(o, get), s); }});
        parameters_.push_back(std::move(p));
    }
    return *this;
}

template <class Options>
Parameter& ParameterSet<Options>::parameter(const std::string& name) {
    for (Parameter& p : parameters_)
        if (p.name() == name) return p;
    throw std::logic_error("no parameter '" + name + "'");
}

template <class Options>
Options ParameterSet<Options>::read(const Settings& settings) const {
    Options o = defaults_;
    for (std::size_t k = 0; k < parameters_.size(); ++k)
        if (settings.has(parameters_[k].name())) bindings_[k].read(o, settings);
    return o;
}

}  // namespace canonform
