#include "canonform/canonical/method_registry.h"

#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/canonical/geodesic_canonical_form.h"
#include "canonform/surface/mesh_topology.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <sstream>

namespace canonform {

namespace {

// --- the built-in methods -------------------------------------------------------------------------

/// `smacof`: the method runs SMACOF (else the parameters are accepted and do not change the result).
std::vector<MethodParameter> smacof_parameters(const char* max_iterations, bool smacof = true) {
    return {{"tolerance", "1e-5", "SMACOF stops when an iteration lowers the stress by less than this fraction",
             0, 1, false, {}, true, false, "tol"},
            {"max_iterations", max_iterations, "SMACOF iteration cap", 1, 1e7, true, {}, true, false, "max-iter"},
            {"acceleration", to_string(kDefaultSmacofAcceleration),
             "SMACOF acceleration: none (plain Guttman steps), relaxed, rre, mpe (vector extrapolation), anderson; "
             "every method keeps the stress from increasing",
             0, 0, false, smacof_acceleration_names(), smacof}};
}

/// The SMACOF settings every SMACOF-based method reads.
void read_smacof_settings(const MethodSettings& s, SmacofOptions* o) {
    o->tolerance = s.number("tolerance");
    o->max_iterations = s.integer("max_iterations");
    o->acceleration = parse_smacof_acceleration(s.text("acceleration"));
}

CanonicalMethod none_method() {
    CanonicalMethod m;
    m.name = "none";
    m.label = "none";
    m.help = "the mesh itself (retrieval on the original meshes)";
    m.run = [](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const MethodSettings&, const MethodContext& c) {
        if (c.validate) validate_mesh(V, F);  // the same meshes as every other method, NaN never passed on
        CanonicalForm r;
        r.V = V;
        r.summary = {{"method", std::string("none")}};
        r.description = "the mesh itself (" + std::to_string(V.rows()) + " vertices)";
        return r;
    };
    return m;
}

CanonicalMethod euclidean_method(CanonicalVariant variant) {
    const bool a = variant == CanonicalVariant::A;
    CanonicalMethod m;
    m.name = a ? "euclidean-A" : "euclidean-N";
    m.label = a ? "A" : "N";
    m.family = MethodFamily::Euclidean;
    m.help = a ? "Euclidean canonical form, variant A (extra random feature points, beta 10)"
               : "Euclidean canonical form, variant N (normalised weights, eq. 10, beta 130)";
    m.parameters = {
        {"alpha", "10", "target distance of every feature-point pair, in units of the mesh radius", 1e-6, 1e6},
        {"beta", a ? "10" : "130", "edge-preservation weight (0: the variant's default)", 0, 1e9, false, {}, true, true},
        {"ring", "2", "k of the k-ring in which a feature point is a strict maximum", 1, 10, true},
        {"seed", "0", "seed of variant A's random feature points", 0, 4294967295.0, true}};
    for (auto& p : smacof_parameters("1000")) m.parameters.push_back(p);
    m.parameters.push_back({"solver", "auto", "linear solver of SMACOF and the conformal factor", 0, 0, false,
                            {"auto", "direct", "multigrid"}, false});
    m.run = [variant](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const MethodSettings& s,
                      const MethodContext& c) {
        EuclideanCanonicalFormOptions o;
        o.variant = variant;
        o.alpha = s.number("alpha");
        o.beta = s.number("beta");
        o.features.ring = s.integer("ring");
        o.features.seed = static_cast<std::uint64_t>(s.number("seed"));
        read_smacof_settings(s, &o.smacof);
        const std::string& solver = s.text("solver");
        o.linear_solver = solver == "direct"      ? LinearSolver::Direct
                          : solver == "multigrid" ? LinearSolver::Multigrid
                                                  : LinearSolver::Auto;
        o.progress = c.progress;
        o.validate = c.validate;
        EuclideanCanonicalFormResult e = euclidean_canonical_form(V, F, o);
        CanonicalForm r;
        r.V = std::move(e.V);
        r.quality = std::move(e.phi);
        r.features = e.features;
        // Grouped: the method, its feature points, the SMACOF run, the result, the timings.
        const std::string variant_name = variant == CanonicalVariant::A ? "A" : "N";
        r.summary = {{"method", std::string("euclidean")}, {"variant", variant_name}, {"alpha", o.alpha},
                     {"beta", e.beta},
                     {"feature_points", static_cast<int>(e.features.size())}, {"maxima", e.num_maxima},
                     {"random", e.num_random},
                     {"iterations", e.iterations}, {"acceleration", std::string(to_string(o.smacof.acceleration))},
                     {"extrapolations", e.extrapolations}, {"rejections", e.rejections}, {"converged", e.converged},
                     {"initial_stress", e.initial_stress}, {"final_stress", e.final_stress},
                     {"solver", std::string(to_string(e.linear_solver))},
                     {"mean_relative_edge_change", e.mean_relative_edge_change}, {"seconds", e.seconds},
                     {"conformal_factor_seconds", e.conformal_factor_seconds}, {"setup_seconds", e.setup_seconds},
                     {"smacof_seconds", e.smacof_seconds}};
        std::ostringstream d;
        d << "variant " << variant_name << ", alpha " << o.alpha << ", beta "
          << e.beta << ": " << V.rows() << " vertices, " << e.features.size() << " feature points ("
          << e.num_maxima << " maxima, " << e.num_random << " random), " << e.iterations << " SMACOF iterations ("
          << to_string(o.smacof.acceleration) << ")"
          << (e.converged ? "" : " (iteration cap reached)") << ", stress " << e.initial_stress << " -> "
          << e.final_stress << ", mean relative edge-length change " << e.mean_relative_edge_change << ", "
          << e.seconds << " s";
        r.description = d.str();
        return r;
    };
    return m;
}

CanonicalMethod geodesic_method(MdsMethod mds) {
    CanonicalMethod m;
    m.family = MethodFamily::Geodesic;
    switch (mds) {
    case MdsMethod::LeastSquares:
        m.name = "geodesic-ls";
        m.label = "least squares";
        m.help = "geodesic canonical form, least-squares MDS (SMACOF on all pairs; the paper's LS)";
        break;
    case MdsMethod::Classical:
        m.name = "geodesic-classical";
        m.label = "classical";
        m.help = "geodesic canonical form, classical MDS (the paper's C)";
        break;
    case MdsMethod::Landmark:
        m.name = "geodesic-fast";
        m.label = "fast";
        m.help = "geodesic canonical form, fast (landmark) MDS (the paper's F)";
        break;
    }
    m.parameters = smacof_parameters("500", mds == MdsMethod::LeastSquares);
    m.parameters.push_back({"max_memory_gib", "4", "refuse meshes whose estimated memory exceeds this (GiB)", 0, 1e6,
                            false, {}, false});
    m.parameters.push_back({"max_seconds", "600", "refuse meshes whose estimated time exceeds this (s)", 0, 1e9, false,
                            {}, false});
    const std::string name = m.name;
    m.run = [mds, name](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const MethodSettings& s,
                        const MethodContext& c) {
        GeodesicCanonicalFormOptions o;
        o.method = mds;
        read_smacof_settings(s, &o.mds.smacof);
        o.max_memory_gib = s.number("max_memory_gib");
        o.max_seconds = s.number("max_seconds");
        o.threads = c.threads;
        o.progress = c.progress;
        GeodesicCanonicalFormResult g = geodesic_canonical_form(V, F, o);
        CanonicalForm r;
        r.V = std::move(g.V);
        const std::string acceleration = mds == MdsMethod::LeastSquares ? to_string(o.mds.smacof.acceleration) : "none";
        r.summary = {{"method", name}, {"iterations", g.iterations}, {"acceleration", acceleration},
                     {"initial_stress", g.initial_stress}, {"final_stress", g.final_stress},
                     {"mean_relative_edge_change", g.mean_relative_edge_change},
                     {"geodesic_seconds", g.geodesic_seconds}, {"mds_seconds", g.mds_seconds}, {"seconds", g.seconds},
                     {"estimated_seconds", g.estimate.seconds}, {"estimated_bytes", g.estimate.bytes}};
        std::ostringstream d;
        d << name << ": " << V.rows() << " vertices (estimated " << g.estimate.describe() << "), geodesics "
          << g.geodesic_seconds << " s, MDS " << g.mds_seconds << " s (" << g.iterations << " iterations, stress "
          << g.initial_stress << " -> " << g.final_stress << "), mean relative edge-length change "
          << g.mean_relative_edge_change << ", " << g.seconds << " s";
        r.description = d.str();
        return r;
    };
    return m;
}

/// The built-in methods, in the order the tool and the filters list them. A new method: one line.
std::vector<CanonicalMethod> builtin_methods() {
    return {none_method(),
            euclidean_method(CanonicalVariant::A),
            euclidean_method(CanonicalVariant::N),
            geodesic_method(MdsMethod::LeastSquares),
            geodesic_method(MdsMethod::Classical),
            geodesic_method(MdsMethod::Landmark)};
}

// --- the registry ----------------------------------------------------------------------------------

std::vector<CanonicalMethod>& registry() {
    static std::vector<CanonicalMethod> methods = builtin_methods();
    return methods;
}

std::mutex& registry_mutex() {
    static std::mutex m;
    return m;
}

std::string names() {
    std::string s;
    for (const auto& m : registry()) s += (s.empty() ? "" : ", ") + m.name;
    return s;
}

bool parse_number(const std::string& text, double* value) {
    if (text.empty()) return false;
    char* end = nullptr;
    *value = std::strtod(text.c_str(), &end);
    return *end == '\0';
}

}  // namespace

void MethodParameter::check(const std::string& value) const {
    if (!choices.empty()) {
        if (std::find(choices.begin(), choices.end(), value) != choices.end()) return;
        std::string list;
        for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
        throw InputError(name + " must be one of " + list + ", got '" + value + "'");
    }
    double v = 0;
    const bool ok = parse_number(value, &v) && std::isfinite(v) && (!integer || v == std::floor(v)) &&
                    ((min == 0 && max == 0) || (v >= min && v <= max));
    if (ok) return;
    std::ostringstream m;
    m << name << " must be ";
    if (zero_means_default)
        m << "a positive number (or 0 for the default)";
    else
        m << (integer ? "a whole number" : "a finite number");
    if ((min != 0 || max != 0) && !zero_means_default) m << " between " << min << " and " << max;
    m << ", got '" << value << "'";
    throw InputError(m.str());
}

double MethodSettings::number(const std::string& name) const { return std::strtod(text(name).c_str(), nullptr); }

int MethodSettings::integer(const std::string& name) const { return static_cast<int>(number(name)); }

const std::string& MethodSettings::text(const std::string& name) const {
    const auto it = values_.find(name);
    if (it == values_.end()) throw std::logic_error("method parameter '" + name + "' not set");
    return it->second;
}

const MethodParameter* CanonicalMethod::parameter(const std::string& n) const {
    for (const auto& p : parameters)
        if (p.name == n) return &p;
    return nullptr;
}

MethodSettings CanonicalMethod::settings(const std::vector<std::pair<std::string, std::string>>& given) const {
    std::map<std::string, std::string> v;
    for (const auto& p : parameters) v[p.name] = p.default_value;
    for (const auto& [key, value] : given) {
        const MethodParameter* p = parameter(key);
        if (!p) {
            std::vector<std::string> takers;
            for (const auto& m : registry())
                if (m.parameter(key)) takers.push_back(m.name);
            std::string who;
            for (size_t k = 0; k < takers.size(); ++k)
                who += (k == 0 ? "" : k + 1 == takers.size() ? " and " : ", ") + takers[k];
            throw InputError("method '" + name + "' has no parameter '" + key + "'" +
                             (takers.empty() ? std::string(": no method takes it") : ": only " + who + " take " + key));
        }
        try {
            p->check(value);
        } catch (const InputError& e) {
            throw InputError("method '" + name + "': " + e.what());
        }
        double number = 0;
        const bool zero = p->zero_means_default && parse_number(value, &number) && number == 0;
        if (!zero) v[key] = value;
    }
    return MethodSettings(std::move(v));
}

const std::vector<CanonicalMethod>& canonical_methods() { return registry(); }

const CanonicalMethod& canonical_method(const std::string& name) {
    for (const auto& m : registry())
        if (m.name == name) return m;
    throw InputError("unknown method '" + name + "' (" + names() + ")");
}

std::vector<const CanonicalMethod*> canonical_methods_of(MethodFamily family) {
    std::vector<const CanonicalMethod*> out;
    for (const auto& m : registry())
        if (m.family == family) out.push_back(&m);
    return out;
}

void register_canonical_method(CanonicalMethod method) {
    std::lock_guard<std::mutex> lock(registry_mutex());
    for (const auto& m : registry())
        if (m.name == method.name) throw InputError("a method called '" + method.name + "' exists already");
    if (method.name.empty() || method.name.find_first_of(":,=_ ") != std::string::npos)
        throw InputError("a method name must be non-empty without ':', ',', '=', '_' or spaces: '" + method.name + "'");
    registry().push_back(std::move(method));
}

void unregister_canonical_method(const std::string& name) {
    std::lock_guard<std::mutex> lock(registry_mutex());
    auto& r = registry();
    r.erase(std::remove_if(r.begin(), r.end(), [&](const CanonicalMethod& m) { return m.name == name; }), r.end());
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
        if (!p.affects_result) continue;
        k << "|" << p.name << "=";
        if (p.choices.empty())
            k << s.number(p.name);
        else
            k << s.text(p.name);
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

}  // namespace canonform
