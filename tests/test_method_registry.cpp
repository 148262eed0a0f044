// The method registry: names, parameters and calls parsed both ways, and a method added at run
// time picked up by everything that lists methods (the filters' enums, method specs, runs).
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/canonical/method_registry.h"
#include "canonform/procedural/procedural_meshes.h"

#include "canonical_filter_table.h"

#include <gtest/gtest.h>

using namespace canonform;

namespace {

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

/// A toy method: the mesh scaled by `scale` about its centroid.
CanonicalMethod toy_method() {
    CanonicalMethod m;
    m.name = "toy-scaled";
    m.label = "toy";
    m.family = MethodFamily::Geodesic;
    m.help = "the mesh scaled about its centroid (a test method)";
    m.parameters = {{"scale", "2", "scale factor", 0.1, 10}};
    m.run = [](const Eigen::MatrixXd& V, const Eigen::MatrixXi&, const MethodSettings& s, const MethodContext&) {
        CanonicalForm r;
        const Eigen::RowVector3d c = V.colwise().mean();
        r.V = ((V.rowwise() - c) * s.number("scale")).rowwise() + c;
        r.summary = {{"method", std::string("toy-scaled")}, {"scale", s.number("scale")}};
        return r;
    };
    return m;
}

}  // namespace

TEST(MethodRegistry, BuiltInMethodsAndFamilies) {
    std::vector<std::string> names;
    for (const auto& m : canonical_methods()) names.push_back(m.name);
    EXPECT_EQ(names, (std::vector<std::string>{"none", "euclidean-A", "euclidean-N", "geodesic-ls",
                                               "geodesic-classical", "geodesic-fast"}));
    ASSERT_EQ(canonical_methods_of(MethodFamily::Euclidean).size(), 2u);
    EXPECT_EQ(canonical_methods_of(MethodFamily::Euclidean)[1]->label, "N");
    EXPECT_EQ(canonical_methods_of(MethodFamily::Geodesic)[2]->label, "fast");
    EXPECT_NE(message_of([] { canonical_method("euclidean-B"); }).find("euclidean-A, euclidean-N"), std::string::npos);
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
    EXPECT_EQ(parse_method_spec("euclidean-N:beta=130").cache_key(), parse_method_spec("euclidean-N").cache_key());
    EXPECT_EQ(parse_method_spec("euclidean-N:beta=0").cache_key(), parse_method_spec("euclidean-N").cache_key());
    EXPECT_NE(parse_method_spec("euclidean-N:beta=65").cache_key(), parse_method_spec("euclidean-N").cache_key());
    // Run-only parameters are not part of the key.
    EXPECT_EQ(parse_method_spec("geodesic-ls:max_seconds=5").cache_key(), parse_method_spec("geodesic-ls").cache_key());
}

TEST(MethodRegistry, BadSpecsNameTheProblem) {
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:beta=x"); }).find("beta must be a positive number"),
              std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:beta=nan"); }).find("beta must be"), std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:beta=-1"); }).find("beta must be"), std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:ring=2.5"); }).find("ring must be a whole number"),
              std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:solver=magic"); }).find("auto, direct, multigrid"),
              std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("geodesic-ls:beta=5"); }).find("only euclidean-A and euclidean-N take"),
              std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("euclidean-N:beta"); }).find("KEY=VALUE"), std::string::npos);
    EXPECT_NE(message_of([] { parse_method_spec("geodesic-ls:acceleration=fast"); })
                  .find("none, relaxed, rre, mpe, anderson"),
              std::string::npos);
}

TEST(MethodRegistry, EverySmacofMethodTakesAnAcceleration) {
    for (const char* name : {"euclidean-A", "euclidean-N", "geodesic-ls"}) {
        const MethodParameter* p = canonical_method(name).parameter("acceleration");
        ASSERT_NE(p, nullptr) << name;
        EXPECT_EQ(p->default_value, "rre");
        EXPECT_EQ(p->choices, smacof_acceleration_names());
        EXPECT_TRUE(p->affects_result);
    }
    // Part of the cache key where it changes the result; not for MDS without SMACOF.
    EXPECT_NE(parse_method_spec("euclidean-N:acceleration=none").cache_key(), parse_method_spec("euclidean-N").cache_key());
    EXPECT_EQ(parse_method_spec("euclidean-N:acceleration=rre").cache_key(), parse_method_spec("euclidean-N").cache_key());
    EXPECT_EQ(parse_method_spec("geodesic-fast:acceleration=none").cache_key(),
              parse_method_spec("geodesic-fast").cache_key());
    // The run reads it: plain steps give the direct call's plain result.
    const Figure fig = make_figure(800, figure_pose(1));
    const CanonicalForm r = canonical_method("euclidean-N").run(
        fig.mesh.V, fig.mesh.F, parse_method_spec("euclidean-N:acceleration=none").settings(), {});
    EuclideanCanonicalFormOptions o;
    o.smacof.acceleration = SmacofAcceleration::None;
    const EuclideanCanonicalFormResult e = euclidean_canonical_form(fig.mesh.V, fig.mesh.F, o);
    EXPECT_EQ((r.V - e.V).cwiseAbs().maxCoeff(), 0.0);
}

TEST(MethodRegistry, RunsMatchTheDirectCall) {
    const Figure fig = make_figure(800, figure_pose(1));
    const CanonicalForm r = canonical_method("euclidean-N").run(fig.mesh.V, fig.mesh.F,
                                                                parse_method_spec("euclidean-N").settings(), {});
    const EuclideanCanonicalFormResult e = euclidean_canonical_form(fig.mesh.V, fig.mesh.F);
    EXPECT_EQ((r.V - e.V).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(r.features, e.features);
    EXPECT_FALSE(r.description.empty());
    const CanonicalForm none = canonical_method("none").run(fig.mesh.V, fig.mesh.F, {}, {});
    EXPECT_EQ(none.V, fig.mesh.V);
}

TEST(MethodRegistry, AMethodAddedAtRunTimeIsPickedUpEverywhere) {
    register_canonical_method(toy_method());
    EXPECT_THROW(register_canonical_method(toy_method()), InputError);  // names are unique
    // Method specs and their runs.
    const MethodSpec spec = parse_method_spec("toy-scaled:scale=3");
    EXPECT_EQ(spec.folder(), "toy-scaled_scale3");
    const Figure fig = make_figure(600, figure_pose(0));
    const CanonicalForm r = spec.method().run(fig.mesh.V, fig.mesh.F, spec.settings(), {});
    const Eigen::RowVector3d c = fig.mesh.V.colwise().mean();
    EXPECT_NEAR((r.V.row(0) - c).norm(), 3 * (fig.mesh.V.row(0) - c).norm(), 1e-9);
    EXPECT_NE(message_of([] { parse_method_spec("toy-scaled:scale=50"); }).find("between"), std::string::npos);
    // The filter of its family lists it in its enum.
    const auto table = plugin::make_filter_table();
    const auto& geodesic = plugin::filter_spec(table, int(plugin::FilterId::GeodesicCanonicalForm));
    const auto& choices = geodesic.params[0].choices;
    EXPECT_EQ(choices.back(), "toy");
    EXPECT_EQ(choices.size(), 4u);
    unregister_canonical_method("toy-scaled");
    EXPECT_THROW(parse_method_spec("toy-scaled"), InputError);
    EXPECT_EQ(plugin::filter_spec(plugin::make_filter_table(), int(plugin::FilterId::GeodesicCanonicalForm))
                  .params[0].choices.size(), 3u);
}
