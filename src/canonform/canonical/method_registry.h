// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the canonical-form methods by name - the one list the tool, `retrieve`, the benchmarks
// and the MeshLab filters read.
//
// A method is a name ("euclidean-N"), a label for a filter's enum ("N"), the filter that lists it
// (its family), its parameters (common/parameters.h: defined once, next to the algorithm's
// options, e.g. euclidean_canonical_form_parameters()) and a run function. A method with
// parameter values is written "NAME[:KEY=VALUE[:KEY=VALUE...]]" ("euclidean-N:beta=65"):
// parse_method_spec() reads that and MethodSpec::to_string() writes it back, so the name, the
// options and the call are parsed both ways. Built-in methods (method_registry.cpp):
//
//   none                 the mesh itself (retrieval on the original meshes)
//   euclidean-A, -N      Pickup et al. 2015, variants A and N (euclidean_canonical_form.h)
//   geodesic-ls, -classical, -fast   Elad and Kimmel's geodesic forms with least-squares,
//                        classical or landmark MDS (geodesic_canonical_form.h)
//
// Adding a method (docs/extending.md): its own .h/.cpp pair (the algorithm, its options and their
// ParameterSet, and a function that makes its CanonicalMethod) and one line in builtin_methods()
// in method_registry.cpp. The tool's `canonical --method` and its options, `retrieve --method`,
// the benchmarks, the filter whose family it names (its enum and its parameters), pymeshlab, the
// .mlx scripts and the parameter listing of the docs pick it up.
//
// The registry may be read from any thread while another registers or unregisters a method: every
// access holds its lock, and a method's object never moves or dies (an unregistered method is kept
// until exit), so a reference or pointer handed out stays valid.
#pragma once

#include "canonform/common/errors.h"
#include "canonform/common/parameters.h"
#include "canonform/surface/conformal_factor.h"

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

/// The parameter values of one run (common/parameters.h): every parameter of the method, at its
/// default or as given.
using MethodSettings = Settings;

/// A store of conformal factors for one mesh: returns the one kept under `key` (the settings it
/// was computed with), or calls `compute` and may keep its result. A collection run with both
/// Euclidean variants computes each mesh's conformal factor once (retrieval/experiment.cpp); a kept
/// result may hold only `normalized` and `ordering`, what the Euclidean form reads.
using ConformalFactorMemo = std::function<surface::ConformalFactorResult(
    const std::string& key, const std::function<surface::ConformalFactorResult()>& compute)>;

/// What a run may use besides its parameters.
struct MethodContext {
    int threads = 0;                        ///< threads for the method's own parallel loops (0 = every core)
    ProgressFn progress;                    ///< optional progress callback
    bool validate = true;                   ///< validate the mesh first (off only if the caller just did)
    ConformalFactorMemo conformal_factors;  ///< optional, for this mesh (Euclidean methods use it)
};

/// A value of a run's summary: what the tool's --json prints and a filter returns to pymeshlab.
using SummaryValue = std::variant<double, int, bool, std::string>;

/// Result of a method's run.
struct CanonicalForm {
    Eigen::MatrixXd V;          ///< the form, #V x 3 (same vertex order and faces)
    Eigen::VectorXd quality;    ///< per-vertex conformal factor where the method has one (else empty)
    std::vector<int> features;  ///< feature points where the method has them
    std::vector<std::pair<std::string, SummaryValue>> summary;  ///< iterations, stresses, times... in order
    std::string description;  ///< one line for a log ("... 126 iterations, stress a -> b, 0.17 s")
};

/// A canonical-form method.
struct CanonicalMethod {
    std::string name;   ///< "euclidean-N"
    std::string label;  ///< its entry in its filter's enum ("N")
    MethodFamily family = MethodFamily::None;
    bool family_default = false;        ///< its filter's default entry, the tool's default of the family
    std::string help;                   ///< one line, for --help
    std::vector<Parameter> parameters;  ///< with this method's defaults
    std::function<CanonicalForm(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                const MethodSettings& settings, const MethodContext& context)>
        run;

    const Parameter* parameter(const std::string& name) const;
    /// Every parameter at its default, then `given` (checked) on top.
    MethodSettings settings(const std::vector<std::pair<std::string, std::string>>& given = {}) const;
};

/// Every method, built-in first, in registration order (a snapshot: pointers to methods that stay
/// valid until exit).
std::vector<const CanonicalMethod*> canonical_methods();
/// The method called `name`; InputError listing the names if there is none.
const CanonicalMethod& canonical_method(const std::string& name);
/// The methods a filter lists, in order (their labels make the filter's enum).
std::vector<const CanonicalMethod*> canonical_methods_of(MethodFamily family);
/// The default method of a family (its filter's default entry; InputError if it has none).
const CanonicalMethod& default_method_of(MethodFamily family);
/// The parameters of a family's methods, each once, in order of first appearance, as its filter
/// lists them: a parameter the methods give different defaults takes 0 if it is
/// zero_means_default (std::logic_error otherwise, and when two methods define a name differently).
std::vector<Parameter> family_parameters(MethodFamily family);
/// Adds a method (InputError if the name is taken). For extensions and tests; built-in methods
/// are listed in method_registry.cpp.
void register_canonical_method(CanonicalMethod method);
/// Removes a method added by register_canonical_method() from the lists (no-op for an unknown
/// name); its object is kept, so that references taken before stay valid.
void unregister_canonical_method(const std::string& name);

/// A method with parameter values, as written "NAME[:KEY=VALUE...]".
struct MethodSpec {
    std::string name;                                        ///< the method's name
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
