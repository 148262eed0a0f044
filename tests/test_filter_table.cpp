// SPDX-License-Identifier: GPL-3.0-or-later
// The filter tables of both plugins: names, the parameters derived from the library's definitions
// (common/parameters.h), the shipped .mlx scripts and the names pymeshlab scripts use.
#include "canonical_filter_table.h"
#include "view_filter_table.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/views/view_parameters.h"

#include <gtest/gtest.h>

#include <cctype>
#include <climits>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

using namespace canonform;
using namespace canonform::meshlab;
using namespace canonform::surface;
using namespace canonform::canonical;

namespace {

std::vector<const FilterSpec*> all_filters() {
    std::vector<const FilterSpec*> all;
    for (const auto& f : filter_table()) all.push_back(&f);
    for (const auto& f : view_filter_table()) all.push_back(&f);
    return all;
}

}  // namespace

TEST(FilterTable, NamesAreUniqueAndParametersSnakeCase) {
    std::set<std::string> names, python;
    const std::regex snake("^[a-z][a-z0-9]*(_[a-z0-9]+)*$");
    for (const FilterSpec* f : all_filters()) {
        EXPECT_TRUE(names.insert(f->name).second) << f->name;  // menu names unique over both plugins
        EXPECT_TRUE(python.insert(f->python_name).second) << f->python_name;
        EXPECT_TRUE(std::regex_match(f->python_name, snake)) << f->python_name;
        std::set<std::string> params;
        for (const auto& p : f->params) {
            EXPECT_TRUE(std::regex_match(p.name(), snake)) << p.name();
            EXPECT_TRUE(params.insert(p.name()).second) << f->name << ": " << p.name() << " twice";
            EXPECT_NO_THROW(p.check(p.default_value())) << p.name();
            EXPECT_FALSE(p.help().empty()) << p.name();
            EXPECT_FALSE(p.label().empty()) << p.name();
        }
    }
    // Ids are the positions (MeshLab's filter ids within a plugin).
    for (const auto* t : {&filter_table(), &view_filter_table()})
        for (size_t k = 0; k < t->size(); ++k) EXPECT_EQ((*t)[k].id, static_cast<int>(k));
}

// MeshLab shows a parameter as RichBool, RichInt (a C int), RichFloat (float in 2020.09), RichEnum
// (an index) or RichString: every range must fit the type, and a default must be a value the type
// holds exactly where the filter reads it back (an int, an enum index).
TEST(FilterTable, EveryParameterFitsItsMeshLabType) {
    for (const FilterSpec* f : all_filters())
        for (const Parameter& p : f->params) {
            SCOPED_TRACE(f->name + ": " + p.name());
            if (p.type() == ParameterType::Int) {
                EXPECT_GE(p.min(), INT_MIN);
                EXPECT_LE(p.max(), INT_MAX);
            }
            if (p.type() == ParameterType::Float) {
                EXPECT_LE(std::abs(p.max()), 3.4e38);
                EXPECT_LE(std::abs(p.min()), 3.4e38);
            }
            if (p.type() == ParameterType::Choice) {
                EXPECT_FALSE(p.choices().empty());
                EXPECT_LT(default_number(p), p.choices().size());
            }
        }
}

// Every registry parameter of a method is a parameter of its family's filter, of the same name,
// type, range and choices (MeshLab shows it with the type and range of its definition), and the
// filter's enum lists the family's methods with the family's default selected.
TEST(FilterTable, EveryMethodParameterIsAParameterOfItsFilter) {
    std::map<MethodFamily, const FilterSpec*> of_family;
    for (const auto& f : filter_table()) {
        for (MethodFamily family : {MethodFamily::Euclidean, MethodFamily::Geodesic}) {
            std::vector<std::string> labels;
            for (const CanonicalMethod* m : canonical_methods_of(family)) labels.push_back(m->label);
            if (!f.params.empty() && f.params[0].choices() == labels) of_family[family] = &f;
        }
    }
    int checked = 0;
    for (const CanonicalMethod* m : canonical_methods()) {
        if (m->family == MethodFamily::None) continue;
        ASSERT_TRUE(of_family.count(m->family)) << m->name << ": no filter lists its family";
        const FilterSpec& f = *of_family[m->family];
        EXPECT_EQ(f.params[0].default_value(), default_method_of(m->family).label);
        for (const Parameter& p : m->parameters) {
            const Parameter* q = find_parameter(f.params, p.name());
            ASSERT_NE(q, nullptr) << m->name << "'s " << p.name() << " is not a parameter of " << f.name;
            EXPECT_EQ(q->type(), p.type()) << p.name();
            EXPECT_EQ(q->min(), p.min()) << p.name();
            EXPECT_EQ(q->max(), p.max()) << p.name();
            EXPECT_EQ(q->choices(), p.choices()) << p.name();
            EXPECT_EQ(q->label(), p.label()) << p.name();
            // The filter's default is the method's, or 0 = "the method's default".
            EXPECT_TRUE(q->default_value() == p.default_value() ||
                        (p.zero_means_default() && q->default_value() == "0"))
                << p.name();
            ++checked;
        }
    }
    EXPECT_GT(checked, 10);
}

// The feature-point, conformal-factor, repair and view parameters are the library's definitions.
TEST(FilterTable, OtherParametersAreTheLibrarysDefinitions) {
    const auto& fp = filter_named(filter_table(), "compute_feature_points");
    for (const Parameter& p : feature_point_parameters().parameters()) {
        const Parameter* q = find_parameter(fp.params, p.name());
        ASSERT_NE(q, nullptr) << p.name();
        EXPECT_EQ(q->default_value(), p.default_value());
        EXPECT_EQ(q->help(), p.help());
    }
    const auto& dv = filter_named(view_filter_table(), "compute_depth_view_descriptor");
    for (const Parameter& p : views::view_descriptor_parameters().parameters()) {
        const Parameter* q = find_parameter(dv.params, p.name());
        ASSERT_NE(q, nullptr) << p.name();
        EXPECT_EQ(q->default_value(), p.default_value());
    }
    // The SIFT default is written by name, and every extractor is described.
    EXPECT_EQ(find_parameter(dv.params, "sift")->default_value(),
              views::sift_backend_name(views::ViewDescriptorOptions().sift.backend));
    for (const std::string& name : views::sift_backend_names())
        EXPECT_FALSE(views::sift_backend_help(name).empty()) << name;
    for (const FilterSpec* f : all_filters()) {
        if (const Parameter* r = find_parameter(f->params, "repair")) {
            EXPECT_EQ(r->help(), repair_parameter().help());
        }
    }
}

TEST(FilterTable, ShippedScriptsListEveryParameterAtItsDefault) {
    for (const auto* t : {&filter_table(), &view_filter_table()})
        for (const auto& f : *t) {
            const std::string dir = t == &filter_table() ? CANONFORM_SCRIPTS_DIR : CANONFORM_VIEW_SCRIPTS_DIR;
            const std::string path = dir + "/" + f.script_file();
            std::ifstream in(path);
            ASSERT_TRUE(in) << path;
            std::stringstream ss;
            ss << in.rdbuf();
            EXPECT_EQ(ss.str(), default_script(f))
                << path << " is out of date: regenerate it with canonform_mlx";
            for (const auto& p : f.params)
                EXPECT_NE(ss.str().find("name=\"" + p.name() + "\""), std::string::npos) << p.name();
        }
}

// The names pymeshlab scripts and .mlx files already use (filters and their keywords, as released):
// a name may be added, never removed or renamed. This list is the promise, not a copy of the table.
TEST(FilterTable, NamesScriptsUseStay) {
    const std::map<std::string, std::pair<std::string, std::vector<std::string>>> released = {
        {"compute_conformal_factor", {"Conformal factor", {"normalize", "colorize", "repair"}}},
        {"compute_feature_points", {"Feature points", {"ring", "fill", "seed", "add_layer", "repair"}}},
        {"generate_euclidean_canonical_form",
         {"Euclidean canonical form",
          {"variant", "alpha", "beta", "ring", "seed", "tolerance", "max_iterations", "acceleration",
           "new_layer", "repair"}}},
        {"generate_geodesic_canonical_form",
         {"Geodesic canonical form",
          {"method", "tolerance", "max_iterations", "acceleration", "max_memory_gib", "max_seconds",
           "new_layer", "repair"}}},
        {"compute_depth_view_descriptor",
         {"Depth view descriptor",
          {"output_file", "codebook_file", "image_size", "views_folder", "seed", "sift"}}}};
    const std::map<std::string, std::vector<std::string>> released_choices = {
        {"variant", {"A", "N"}},
        {"method", {"least squares", "classical", "fast"}},
        {"fill", {"none", "random"}},
        {"acceleration", {"none", "relaxed", "rre", "mpe", "anderson"}}};
    for (const auto& [python, menu_and_keywords] : released) {
        SCOPED_TRACE(python);
        const FilterSpec* f = nullptr;
        for (const FilterSpec* g : all_filters())
            if (g->python_name == python) f = g;
        ASSERT_NE(f, nullptr);
        EXPECT_EQ(f->name, menu_and_keywords.first);
        for (const std::string& k : menu_and_keywords.second) {
            const Parameter* p = find_parameter(f->params, k);
            ASSERT_NE(p, nullptr) << k;
            const auto c = released_choices.find(k);
            if (c != released_choices.end() && p->type() == ParameterType::Choice)
                for (size_t i = 0; i < c->second.size(); ++i) {
                    ASSERT_LT(i, p->choices().size()) << k;
                    EXPECT_EQ(p->choices()[i], c->second[i])
                        << k << ": an enum index scripts use changed meaning";
                }
        }
    }
}

// pymeshlab 2022.2 calls a filter by FilterPlugin::pythonFilterName() (the table's python_name),
// and also registers a deprecated name made from the menu name (lower case, spaces to '_'): no
// name may be taken twice, or pymeshlab's set of functions keeps only one of them.
TEST(FilterTable, PythonNamesForPymeshlab) {
    std::set<std::string> all;
    for (const FilterSpec* f : all_filters()) {
        std::string old = f->name;
        for (char& c : old)
            c = c == ' ' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        EXPECT_TRUE(all.insert(f->python_name).second) << f->python_name;
        EXPECT_TRUE(all.insert(old).second) << old;
    }
}

TEST(FilterTable, ProseFoldsLineBreaksAndIndentationIntoOneSpace) {
    EXPECT_EQ(prose("Computes the\n                 conformal  factor.\n"), "Computes the conformal factor.");
    EXPECT_EQ(prose("\n  lead and trail \t\r\n"), "lead and trail");
    EXPECT_EQ(prose(""), "");
    for (const FilterSpec* f : all_filters()) {
        EXPECT_EQ(f->info.find("  "), std::string::npos) << f->name;
        EXPECT_EQ(f->info.find('\n'), std::string::npos) << f->name;
    }
}

// What MeshLab hands an action is turned into the parameters' texts: numbers with 17 digits, an
// enum's index by name, switches as true/false; a bad index is refused naming the choices.
TEST(FilterTable, ValuesFromMeshLabBecomeTheParametersTexts) {
    const auto& f = filter_named(filter_table(), "generate_euclidean_canonical_form");
    ParamValues v;
    v.values = {{"variant", 0}, {"alpha", 8}, {"tolerance", static_cast<float>(1e-5)}, {"new_layer", 1}};
    const auto texts = v.texts(f.params);
    const std::map<std::string, std::string> m(texts.begin(), texts.end());
    EXPECT_EQ(m.at("variant"), "A");
    EXPECT_EQ(m.at("alpha"), "8");
    EXPECT_EQ(m.at("tolerance"),
              "9.9999997473787516e-06");  // MeshLab 2020.09's float, as it reaches the method
    EXPECT_EQ(m.at("new_layer"), "true");
    EXPECT_EQ(m.count("beta"), 0u);  // not given: the method's default
    v.values["acceleration"] = 9;
    EXPECT_THROW(v.texts(f.params), InputError);
}
