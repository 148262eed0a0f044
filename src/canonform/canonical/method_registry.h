// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the canonical-form methods by name - the one list the tool, `retrieve`, the benchmarks
// and the MeshLab filters read.
//
// A method is a name ("euclidean-N"), a label for a filter's enum ("N"), the filter that lists it
// (its family), its parameters with defaults and ranges, and a run function. A method with
// parameter values is written "NAME[:KEY=VALUE[:KEY=VALUE...]]" ("euclidean-N:beta=65"):
// parse_method_spec() reads that and MethodSpec::to_string() writes it back, so the name, the
// options and the call are parsed both ways. Built-in methods (method_registry.cpp):
//
//   none                 the mesh itself (retrieval on the original meshes)
//   euclidean-A, -N      Pickup et al. 2015, variants A and N (euclidean_canonical_form.h)
//   geodesic-ls, -classical, -fast   Elad and Kimmel's geodesic forms with least-squares,
//                        classical or landmark MDS (geodesic_canonical_form.h)
//
// Adding a method: its own source (the algorithm, and a function that makes its CanonicalMethod)
// and one line in builtin_methods() in method_registry.cpp. The tool's `canonical --method`, its
// options, `retrieve --method`, the benchmarks and the filter whose family it names pick it up.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace canonform::canonical {

/// The MeshLab filter whose method enum lists a method ("Euclidean canonical form": variant,
/// "Geodesic canonical form": method); None for methods no filter offers.
enum class MethodFamily { None, Euclidean, Geodesic };

/// One parameter of a method: NAME=VALUE in a method spec, --NAME in the tool (underscores as
/// dashes, plus `alias`), the filter parameter of the same name.
struct MethodParameter {
    std::string name;                  ///< lower snake_case ("beta", "max_iterations")
    std::string default_value;         ///< as text ("10", "auto")
    std::string help;                  ///< one line, for --help
    double min = 0;                    ///< numbers: closed range [min, max] (both 0: any finite number)
    double max = 0;
    bool integer = false;              ///< numbers: must be whole
    std::vector<std::string> choices = {};  ///< non-empty: the value is one of these words
    bool affects_result = true;        ///< part of the cache key of a retrieval run
    bool zero_means_default = false;   ///< a given 0 stands for the default (a filter's "0 = default")
    std::string alias = {};            ///< a second, older tool option name ("tol"), or empty
    /// Checks `value` (throws InputError naming the parameter, the value and what it must be).
    void check(const std::string& value) const;
};

/// Parameter values of one run (every parameter of the method: defaults and given values).
class MethodSettings {
public:
    MethodSettings() = default;
    explicit MethodSettings(std::map<std::string, std::string> values) : values_(std::move(values)) {}
    double number(const std::string& name) const;
    int integer(const std::string& name) const;
    const std::string& text(const std::string& name) const;
    const std::map<std::string, std::string>& values() const { return values_; }

private:
    std::map<std::string, std::string> values_;
};

/// What a run may use besides its parameters.
struct MethodContext {
    int threads = 0;       ///< threads for the method's own parallel loops (0 = every core)
    ProgressFn progress;   ///< optional progress callback
    bool validate = true;  ///< validate the mesh first (off only if the caller just did)
};

/// A value of a run's summary: what the tool's --json prints and a filter returns to pymeshlab.
using SummaryValue = std::variant<double, int, bool, std::string>;

/// Result of a method's run.
struct CanonicalForm {
    Eigen::MatrixXd V;                  ///< the form, #V x 3 (same vertex order and faces)
    Eigen::VectorXd quality;            ///< per-vertex conformal factor where the method has one (else empty)
    std::vector<int> features;          ///< feature points where the method has them
    std::vector<std::pair<std::string, SummaryValue>> summary;  ///< iterations, stresses, times... in order
    std::string description;            ///< one line for a log ("... 126 iterations, stress a -> b, 0.17 s")
};

/// A canonical-form method.
struct CanonicalMethod {
    std::string name;                          ///< "euclidean-N"
    std::string label;                         ///< its entry in its filter's enum ("N")
    MethodFamily family = MethodFamily::None;
    std::string help;                          ///< one line, for --help
    std::vector<MethodParameter> parameters;
    std::function<CanonicalForm(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const MethodSettings& settings,
                                const MethodContext& context)>
        run;

    const MethodParameter* parameter(const std::string& name) const;
    /// Every parameter at its default, then `given` (checked) on top.
    MethodSettings settings(const std::vector<std::pair<std::string, std::string>>& given = {}) const;
};

/// Every method, built-in first, in registration order.
const std::vector<CanonicalMethod>& canonical_methods();
/// The method called `name`; InputError listing the names if there is none.
const CanonicalMethod& canonical_method(const std::string& name);
/// The methods a filter lists, in order (their labels make the filter's enum).
std::vector<const CanonicalMethod*> canonical_methods_of(MethodFamily family);
/// Adds a method (InputError if the name is taken). For extensions and tests; built-in methods
/// are listed in method_registry.cpp.
void register_canonical_method(CanonicalMethod method);
/// Removes a method added by register_canonical_method() (no-op for an unknown name).
void unregister_canonical_method(const std::string& name);

/// A method with parameter values, as written "NAME[:KEY=VALUE...]".
struct MethodSpec {
    std::string name;                                         ///< the method's name
    std::vector<std::pair<std::string, std::string>> given;  ///< parameters as written, in order

    const CanonicalMethod& method() const { return canonical_method(name); }
    MethodSettings settings() const { return method().settings(given); }
    /// "euclidean-N:beta=65" (parse_method_spec(to_string()) gives this spec back).
    std::string to_string() const;
    /// Folder of its results in a retrieval run: "euclidean-N_beta65".
    std::string folder() const;
    /// What its results depend on: the name and every result-affecting parameter's effective
    /// value, so that "euclidean-N:beta=130" and "euclidean-N" share a cache entry.
    std::string cache_key() const;
};

/// Parses "NAME[:KEY=VALUE...]" (InputError naming the unknown method or parameter, or the bad value).
MethodSpec parse_method_spec(const std::string& text);

}  // namespace canonform::canonical
