// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/canonical/method_registry.h"

#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/canonical/geodesic_canonical_form.h"
#include "canonform/surface/mesh_topology.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>
#include <sstream>

namespace canonform::canonical {

namespace {

// --- the built-in methods -------------------------------------------------------------------------

CanonicalMethod none_method() {
    CanonicalMethod m;
    m.name = "none";
    m.label = "none";
    m.help = "the mesh itself (retrieval on the original meshes)";
    m.run = [](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const MethodSettings&,
               const MethodContext& c) {
        if (c.validate)
            surface::validate_mesh(V, F);  // the same meshes as every other method, NaN never passed on
        CanonicalForm r;
        r.V = V;
        r.summary = {{"method", std::string("none")}};
        r.description = "the mesh itself (" + std::to_string(V.rows()) + " vertices)";
        return r;
    };
    return m;
}

/// The built-in methods, in the order the tool and the filters list them. A new method: one line.
std::vector<CanonicalMethod> builtin_methods() {
    return {none_method(),
            euclidean_method(CanonicalVariant::A),
            euclidean_method(CanonicalVariant::N),
            geodesic_method(numerics::MdsMethod::LeastSquares),
            geodesic_method(numerics::MdsMethod::Classical),
            geodesic_method(numerics::MdsMethod::Landmark)};
}

// --- the registry ----------------------------------------------------------------------------------

/// The methods, in order, and every method ever registered. A std::deque never moves its elements
/// when it grows at the end, and nothing is ever erased from `all`, so a reference handed out
/// stays valid while other threads register and unregister methods.
struct Registry {
    std::mutex mutex;
    std::deque<CanonicalMethod> all;             // every method ever registered (never shrinks)
    std::vector<const CanonicalMethod*> listed;  // the registered ones, in order
    Registry() {
        for (CanonicalMethod& m : builtin_methods()) {
            all.push_back(std::move(m));
            listed.push_back(&all.back());
        }
    }
};

Registry& registry() {
    static Registry r;
    return r;
}

std::string names_of(const std::vector<const CanonicalMethod*>& methods) {
    std::string s;
    for (const CanonicalMethod* m : methods) s += (s.empty() ? "" : ", ") + m->name;
    return s;
}

/// Two parameters of one name in a family's methods are the same parameter but for the default
/// and whether it affects the result.
bool same_definition(const Parameter& a, const Parameter& b) {
    return a.type() == b.type() && a.label() == b.label() && a.help() == b.help() && a.min() == b.min() &&
           a.max() == b.max() && a.choices() == b.choices() &&
           a.zero_means_default() == b.zero_means_default() && a.alias() == b.alias();
}

}  // namespace

const Parameter* CanonicalMethod::parameter(const std::string& n) const {
    return find_parameter(parameters, n);
}

MethodSettings CanonicalMethod::settings(
    const std::vector<std::pair<std::string, std::string>>& given) const {
    for (const auto& [key, value] : given) {
        if (parameter(key)) continue;
        std::vector<std::string> takers;
        for (const CanonicalMethod* m : canonical_methods())
            if (m->parameter(key)) takers.push_back(m->name);
        std::string who;
        for (size_t k = 0; k < takers.size(); ++k)
            who += (k == 0 ? "" : k + 1 == takers.size() ? " and " : ", ") + takers[k];
        throw InputError(
            "method '" + name + "' has no parameter '" + key + "'" +
            (takers.empty() ? std::string(": no method takes it") : ": only " + who + " take " + key));
    }
    try {
        return MethodSettings(parameters, given);
    } catch (const InputError& e) {
        throw InputError("method '" + name + "': " + e.what());
    }
}

std::vector<const CanonicalMethod*> canonical_methods() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    return r.listed;
}

const CanonicalMethod& canonical_method(const std::string& name) {
    const std::vector<const CanonicalMethod*> methods = canonical_methods();
    for (const CanonicalMethod* m : methods)
        if (m->name == name) return *m;
    throw InputError("unknown method '" + name + "' (" + names_of(methods) + ")");
}

std::vector<const CanonicalMethod*> canonical_methods_of(MethodFamily family) {
    std::vector<const CanonicalMethod*> out;
    for (const CanonicalMethod* m : canonical_methods())
        if (m->family == family) out.push_back(m);
    return out;
}

const CanonicalMethod& default_method_of(MethodFamily family) {
    for (const CanonicalMethod* m : canonical_methods_of(family))
        if (m->family_default) return *m;
    throw InputError("no default method in this family");
}

std::vector<Parameter> family_parameters(MethodFamily family) {
    std::vector<Parameter> out;
    for (const CanonicalMethod* m : canonical_methods_of(family))
        for (const Parameter& p : m->parameters) {
            Parameter* seen = nullptr;
            for (Parameter& q : out)
                if (q.name() == p.name()) seen = &q;
            if (!seen) {
                out.push_back(p);
                continue;
            }
            if (!same_definition(*seen, p))
                throw std::logic_error("methods of one family define parameter '" + p.name() +
                                       "' differently");
            if (p.affects_result()) seen->affects_result(true);
            if (seen->default_value() == p.default_value()) continue;
            if (!p.zero_means_default())
                throw std::logic_error("methods of one family give parameter '" + p.name() +
                                       "' different defaults");
            seen->default_value("0");
        }
    return out;
}

void register_canonical_method(CanonicalMethod method) {
    if (method.name.empty() || method.name.find_first_of(":,=_ ") != std::string::npos)
        throw InputError("a method name must be non-empty without ':', ',', '=', '_' or spaces: '" +
                         method.name + "'");
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    for (const CanonicalMethod* m : r.listed)
        if (m->name == method.name) throw InputError("a method called '" + method.name + "' exists already");
    r.all.push_back(std::move(method));
    r.listed.push_back(&r.all.back());
}

void unregister_canonical_method(const std::string& name) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    r.listed.erase(std::remove_if(r.listed.begin(), r.listed.end(),
                                  [&](const CanonicalMethod* m) { return m->name == name; }),
                   r.listed.end());
}

std::string MethodSpec::to_string() const {
    std::string s = name;
    for (const auto& [k, v] : given) s += ":" + k + "=" + v;
    return s;
}

std::string MethodSpec::folder() const {
    std::string s = name;
    for (const auto& [k, v] : given) s += "_" + k + v;
    return s;
}

std::string MethodSpec::cache_key() const {
    const CanonicalMethod& m = method();
    const MethodSettings s = settings();
    std::ostringstream k;
    k.precision(17);
    k << name;
    for (const auto& p : m.parameters) {
        if (!p.affects_result()) continue;
        k << "|" << p.name() << "=";
        if (p.is_number())
            k << s.number(p.name());
        else
            k << s.text(p.name());
    }
    return k.str();
}

MethodSpec parse_method_spec(const std::string& text) {
    MethodSpec spec;
    std::stringstream in(text);
    std::string part;
    std::getline(in, spec.name, ':');
    canonical_method(spec.name);  // throws for an unknown name
    while (std::getline(in, part, ':')) {
        const auto eq = part.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("method '" + text + "': parameters are written KEY=VALUE, got '" + part + "'");
        spec.given.emplace_back(part.substr(0, eq), part.substr(eq + 1));
    }
    spec.settings();  // checks every given parameter
    return spec;
}

}  // namespace canonform::canonical
