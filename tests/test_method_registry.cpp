// SPDX-License-Identifier: GPL-3.0-or-later
// The method registry: names, parameters and calls parsed both ways, and a method added at run
// time picked up by everything that lists methods (the filters' enums, method specs, runs).
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/canonical/geodesic_canonical_form.h"
#include "canonform/canonical/method_registry.h"
#include "canonform/procedural/procedural_meshes.h"

#include "canonical_filter_table.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <thread>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::canonical;
using namespace canonform::procedural;
using canonform::test::message_of;

namespace {

/// A toy method: the mesh scaled by `scale` about its centroid.
CanonicalMethod toy_method() {
    CanonicalMethod m;
    m.name = "toy-scaled";
    m.label = "toy";
    m.family = MethodFamily::Geodesic;
    m.help = "the mesh scaled about its centroid (a test method)";
    m.parameters = {
        Parameter::number("scale", 0.1, 10).default_value("2").label("Scale").help("scale factor")};
    m.run = [](const Eigen::MatrixXd& V, const Eigen::MatrixXi&, const MethodSettings& s,
               const MethodContext&) {
        CanonicalForm r;
        const Eigen::RowVector3d c = V.colwise().mean();
        r.V = ((V.rowwise() - c) * s.number("scale")).rowwise() + c;
        r.summary = {{"method", std::string("toy-scaled")}, {"scale", s.number("scale")}};
        return r;
    };
    return m;
}

}  // namespace

TEST(MethodRegistry, NamesLabelsAndFamiliesAreConsistent) {
    // Enumerated, not listed: a new method is checked by the same rules.
    const auto methods = canonical_methods();
    ASSERT_FALSE(methods.empty());
    EXPECT_EQ(methods.front()->name, "none");  // retrieval's baseline comes first
    std::set<std::string> names;
    for (const CanonicalMethod* m : methods) {
        SCOPED_TRACE(m->name);
        EXPECT_TRUE(names.insert(m->name).second);
        EXPECT_EQ(&canonical_method(m->name), m);
        EXPECT_EQ(m->name.find_first_of(":,=_ "), std::string::npos);
        EXPECT_FALSE(m->help.empty());
        EXPECT_TRUE(m->run);
        std::set<std::string> params;
        for (const Parameter& p : m->parameters) {
            EXPECT_TRUE(params.insert(p.name()).second) << p.name();
            EXPECT_NO_THROW(p.check(p.default_value())) << p.name();
        }
    }
    for (MethodFamily family : {MethodFamily::Euclidean, MethodFamily::Geodesic}) {
        std::set<std::string> labels;
        int defaults = 0;
        for (const CanonicalMethod* m : canonical_methods_of(family)) {
            EXPECT_TRUE(labels.insert(m->label).second) << m->label;
            defaults += m->family_default;
        }
        EXPECT_EQ(defaults, 1);
        EXPECT_NO_THROW(family_parameters(family));
    }
    // The defaults of the families are the algorithms' option defaults.
    EXPECT_EQ(default_method_of(MethodFamily::Euclidean).name, "euclidean-N");
    EXPECT_EQ(default_method_of(MethodFamily::Geodesic).name, "geodesic-ls");
    const std::string unknown = message_of([] { canonical_method("euclidean-B"); });
    for (const CanonicalMethod* m : methods) EXPECT_NE(unknown.find(m->name), std::string::npos) << m->name;
}

// A method's parameters are the definitions bound to its options (common/parameters.h): each
// default is the options' default, and every value given reaches the options the run uses.
TEST(MethodRegistry, ParametersAreTheOptionsDefaults) {
    const auto eN = EuclideanCanonicalFormOptions::of_variant(CanonicalVariant::N);
    const MethodSettings s = canonical_method("euclidean-N").settings();
    EXPECT_EQ(s.number("alpha"), eN.alpha);
    EXPECT_EQ(s.number("beta"), 130);
    EXPECT_EQ(s.integer("ring"), eN.features.ring);
    EXPECT_EQ(s.number("tolerance"), eN.smacof.tolerance);
    EXPECT_EQ(s.integer("max_iterations"), eN.smacof.max_iterations);
    EXPECT_EQ(s.text("acceleration"), to_string(eN.smacof.acceleration));
    EXPECT_EQ(canonical_method("geodesic-ls").settings().integer("max_iterations"),
              GeodesicCanonicalFormOptions().mds.smacof.max_iterations);
    const auto set = euclidean_canonical_form_parameters();
    const EuclideanCanonicalFormOptions o = set.read({{"alpha", "7.5"},
                                                      {"ring", "3"},
                                                      {"seed", "9"},
                                                      {"tolerance", "1e-4"},
                                                      {"max_iterations", "77"},
                                                      {"acceleration", "anderson"},
                                                      {"solver", "multigrid"}});
    EXPECT_EQ(o.alpha, 7.5);
    EXPECT_EQ(o.features.ring, 3);
    EXPECT_EQ(o.features.seed, 9u);
    EXPECT_EQ(o.smacof.tolerance, 1e-4);
    EXPECT_EQ(o.smacof.max_iterations, 77);
    EXPECT_EQ(o.smacof.acceleration, SmacofAcceleration::Anderson);
    EXPECT_EQ(o.linear_solver, LinearSolver::Multigrid);
    // Every method: its settings at the defaults read back to each parameter's default text.
    for (const CanonicalMethod* m : canonical_methods())
        for (const Parameter& p : m->parameters) EXPECT_EQ(m->settings().text(p.name()), p.default_value());
}

// Every conversion of a text to a number names the parameter and the text.
TEST(MethodRegistry, ConversionsAreChecked) {
    const MethodSettings bad(
        std::map<std::string, std::string>{{"beta", "13O"}, {"ring", "2.5"}, {"on", "yes"}});
    EXPECT_NE(message_of([&] { bad.number("beta"); }).find("beta: '13O'"), std::string::npos);
    EXPECT_NE(message_of([&] { bad.integer("ring"); }).find("ring: '2.5'"), std::string::npos);
    EXPECT_NE(message_of([&] { bad.flag("on"); }).find("on: 'yes'"), std::string::npos);
    EXPECT_THROW(bad.text("missing"), std::logic_error);
    EXPECT_EQ(format_number(10), "10");
    EXPECT_EQ(format_number(1e-5), "1e-5");
    EXPECT_EQ(format_number(130), "130");
    EXPECT_EQ(format_number(1e9), "1e9");
    EXPECT_EQ(format_number(2147483647), "2147483647");
    EXPECT_EQ(format_number(0.1), "0.1");
    for (double v : {10.0, 1e-5, 130.0, 0.1, 1.0 / 3, 4294967295.0, 6e-7, 1e300})
        EXPECT_EQ(std::strtod(format_number(v).c_str(), nullptr), v) << format_number(v);
}

TEST(MethodRegistry, SpecsParseAndPrintBothWays) {
    for (const std::string text : {"none", "euclidean-N", "euclidean-A:beta=5", "euclidean-N:beta=65:ring=3",
                                   "geodesic-ls:tolerance=1e-4"}) {
        const MethodSpec s = parse_method_spec(text);
        EXPECT_EQ(s.to_string(), text);
        EXPECT_EQ(parse_method_spec(s.to_string()).folder(), s.folder());
    }
    EXPECT_EQ(parse_method_spec("euclidean-N:beta=65").folder(), "euclidean-N_beta65");
    // Defaults are per method; a given default and 0 ("the variant's default") share the cache key.
    EXPECT_EQ(parse_method_spec("euclidean-A").settings().number("beta"), 10);
    EXPECT_EQ(parse_method_spec("euclidean-N").settings().number("beta"), 130);
    EXPECT_EQ(parse_method_spec("euclidean-N:beta=130").cache_key(),
              parse_method_spec("euclidean-N").cache_key());
    EXPECT_EQ(parse_method_spec("euclidean-N:beta=0").cache_key(),
              parse_method_spec("euclidean-N").cache_key());
    EXPECT_NE(parse_method_spec("euclidean-N:beta=65").cache_key(),
              parse_method_spec("euclidean-N").cache_key());
    // Run-only parameters are not part of the key.
    EXPECT_EQ(parse_method_spec("geodesic-ls:max_seconds=5").cache_key(),
              parse_method_spec("geodesic-ls").cache_key());
}

TEST(MethodRegistry, BadSpecsNameTheProblem) {
    EXPECT_NE(
        message_of([] { parse_method_spec("euclidean-N:beta=x"); }).find("beta must be a positive number"),
        std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:beta=nan"); }).find("beta must be"),
              std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:beta=-1"); }).find("beta must be"),
              std::string::npos);
    EXPECT_NE(
        message_of([] { parse_method_spec("euclidean-N:ring=2.5"); }).find("ring must be a whole number"),
        std::string::npos);
    EXPECT_NE(
        message_of([] { parse_method_spec("euclidean-N:solver=magic"); }).find("auto, direct, multigrid"),
        std::string::npos);
    EXPECT_NE(message_of([] {
                  parse_method_spec("geodesic-ls:beta=5");
              }).find("only euclidean-A and euclidean-N take"),
              std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:beta"); }).find("KEY=VALUE"), std::string::npos);
    EXPECT_NE(message_of([] {
                  parse_method_spec("geodesic-ls:acceleration=fast");
              }).find("none, relaxed, rre, mpe, anderson"),
              std::string::npos);
}

TEST(MethodRegistry, EverySmacofMethodTakesAnAcceleration) {
    for (const char* name : {"euclidean-A", "euclidean-N", "geodesic-ls"}) {
        const Parameter* p = canonical_method(name).parameter("acceleration");
        ASSERT_NE(p, nullptr) << name;
        EXPECT_EQ(p->default_value(), "rre");
        EXPECT_EQ(p->choices(), smacof_acceleration_names());
        EXPECT_TRUE(p->affects_result());
    }
    // Part of the cache key where it changes the result; not for MDS without SMACOF.
    EXPECT_NE(parse_method_spec("euclidean-N:acceleration=none").cache_key(),
              parse_method_spec("euclidean-N").cache_key());
    EXPECT_EQ(parse_method_spec("euclidean-N:acceleration=rre").cache_key(),
              parse_method_spec("euclidean-N").cache_key());
    EXPECT_EQ(parse_method_spec("geodesic-fast:acceleration=none").cache_key(),
              parse_method_spec("geodesic-fast").cache_key());
    // The run reads it: plain steps give the direct call's plain result.
    const Figure fig = make_figure(800, figure_pose(1));
    const CanonicalForm r =
        canonical_method("euclidean-N")
            .run(fig.mesh.V, fig.mesh.F, parse_method_spec("euclidean-N:acceleration=none").settings(), {});
    EuclideanCanonicalFormOptions o;
    o.smacof.acceleration = SmacofAcceleration::None;
    const EuclideanCanonicalFormResult e = euclidean_canonical_form(fig.mesh.V, fig.mesh.F, o);
    EXPECT_EQ((r.V - e.V).cwiseAbs().maxCoeff(), 0.0);
}

TEST(MethodRegistry, RunsMatchTheDirectCall) {
    const Figure fig = make_figure(800, figure_pose(1));
    const CanonicalForm r = canonical_method("euclidean-N")
                                .run(fig.mesh.V, fig.mesh.F, parse_method_spec("euclidean-N").settings(), {});
    const EuclideanCanonicalFormResult e = euclidean_canonical_form(fig.mesh.V, fig.mesh.F);
    EXPECT_EQ((r.V - e.V).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(r.features, e.features);
    EXPECT_FALSE(r.description.empty());
    const CanonicalForm none = canonical_method("none").run(fig.mesh.V, fig.mesh.F, {}, {});
    EXPECT_EQ(none.V, fig.mesh.V);
}

TEST(MethodRegistry, AMethodAddedAtRunTimeIsPickedUpEverywhere) {
    const size_t geodesic_params =
        meshlab::filter_named(meshlab::make_filter_table(), "generate_geodesic_canonical_form").params.size();
    register_canonical_method(toy_method());
    EXPECT_THROW(register_canonical_method(toy_method()), InputError);  // names are unique
    // Method specs and their runs.
    const MethodSpec spec = parse_method_spec("toy-scaled:scale=3");
    EXPECT_EQ(spec.folder(), "toy-scaled_scale3");
    const Figure fig = make_figure(600, figure_pose(0));
    const CanonicalForm r = spec.method().run(fig.mesh.V, fig.mesh.F, spec.settings(), {});
    const Eigen::RowVector3d c = fig.mesh.V.colwise().mean();
    EXPECT_NEAR((r.V.row(0) - c).norm(), 3 * (fig.mesh.V.row(0) - c).norm(), 1e-9);
    EXPECT_NE(message_of([] { parse_method_spec("toy-scaled:scale=50"); }).find("between"),
              std::string::npos);
    // The filter of its family lists it in its enum, and its parameter with its type and range.
    const auto table = meshlab::make_filter_table();
    const auto& geodesic = meshlab::filter_named(table, "generate_geodesic_canonical_form");
    EXPECT_EQ(geodesic.params[0].choices().back(), "toy");
    EXPECT_EQ(geodesic.params[0].choices().size(), canonical_methods_of(MethodFamily::Geodesic).size());
    const Parameter* scale = find_parameter(geodesic.params, "scale");
    ASSERT_NE(scale, nullptr);
    EXPECT_EQ(scale->type(), ParameterType::Float);
    EXPECT_EQ(scale->max(), 10);
    EXPECT_EQ(geodesic.params.size(), geodesic_params + 1);
    EXPECT_NE(meshlab::default_script(geodesic).find("<Param name=\"scale\" type=\"RichFloat\" value=\"2\""),
              std::string::npos);
    unregister_canonical_method("toy-scaled");
    EXPECT_THROW(parse_method_spec("toy-scaled"), InputError);
    EXPECT_EQ(
        meshlab::filter_named(meshlab::make_filter_table(), "generate_geodesic_canonical_form").params.size(),
        geodesic_params);
}

// The registry may be read from any thread while another registers and unregisters methods: no
// data race, and a reference taken before stays valid (run under ThreadSanitizer and
// AddressSanitizer by tools/sanitizer_tests.sh).
TEST(MethodRegistry, ReadsAreSafeWhileAnotherThreadRegisters) {
    const CanonicalMethod& none = canonical_method("none");
    const size_t before = canonical_methods().size();
    std::atomic<bool> stop{false};
    std::atomic<long> reads{0};
    std::vector<std::thread> readers;
    for (int t = 0; t < 3; ++t)
        readers.emplace_back([&] {
            while (!stop) {
                const CanonicalMethod& m = canonical_method("euclidean-N");
                if (m.parameter("beta") == nullptr) ADD_FAILURE();
                for (const CanonicalMethod* x : canonical_methods())
                    if (x->name.empty()) ADD_FAILURE();
                if (parse_method_spec("euclidean-A:beta=5").cache_key().empty()) ADD_FAILURE();
                ++reads;
            }
        });
    std::vector<const CanonicalMethod*> taken;
    for (int k = 0; k < 200; ++k) {
        // Interleaved with the readers: each registration waits for a read to finish.
        const long seen = reads.load();
        while (reads.load() == seen) std::this_thread::yield();
        CanonicalMethod m = toy_method();
        m.name = "toy-" + std::to_string(k);
        register_canonical_method(m);
        taken.push_back(&canonical_method(m.name));
        if (k % 2) unregister_canonical_method("toy-" + std::to_string(k - 1));
    }
    stop = true;
    for (auto& t : readers) t.join();
    for (int k = 0; k < 200; ++k) unregister_canonical_method("toy-" + std::to_string(k));
    EXPECT_GE(reads.load(), 200);
    // References handed out stay valid after their method left the list.
    for (size_t k = 0; k < taken.size(); ++k) EXPECT_EQ(taken[k]->name, "toy-" + std::to_string(k));
    EXPECT_EQ(none.name, "none");
    EXPECT_EQ(canonical_methods().size(), before);
}
