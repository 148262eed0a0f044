// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonical_filter_table.h"
#include "view_filter_table.h"

#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

using namespace canonform::meshlab;

TEST(FilterTable, NamesAreUniqueAndParametersSnakeCase) {
    std::set<std::string> names, python;
    const std::regex snake("^[a-z][a-z0-9]*(_[a-z0-9]+)*$");
    for (const auto& f : filter_table()) {
        EXPECT_TRUE(names.insert(f.name).second) << f.name;
        EXPECT_TRUE(python.insert(f.python_name).second) << f.python_name;
        EXPECT_TRUE(std::regex_match(f.python_name, snake)) << f.python_name;
        std::set<std::string> params;
        for (const auto& p : f.params) {
            EXPECT_TRUE(std::regex_match(p.name, snake)) << p.name;
            EXPECT_TRUE(params.insert(p.name).second) << p.name;
            if (p.kind == ParamKind::Enum) {
                EXPECT_LT(p.default_value, p.choices.size());
            }
        }
    }
    EXPECT_EQ(names, (std::set<std::string>{"Conformal factor", "Feature points", "Euclidean canonical form",
                                            "Geodesic canonical form"}));
}

TEST(FilterTable, ViewDescriptorTableFollowsTheSameRules) {
    const std::regex snake("^[a-z][a-z0-9]*(_[a-z0-9]+)*$");
    ASSERT_EQ(view_filter_table().size(), 1u);
    EXPECT_STREQ(view_filter_table()[0].name, "Depth view descriptor");
    for (const auto& p : view_filter_table()[0].params) EXPECT_TRUE(std::regex_match(p.name, snake)) << p.name;
    for (const auto& f : filter_table()) EXPECT_STRNE(f.name, view_filter_table()[0].name);  // menu names unique
}

TEST(FilterTable, ShippedScriptsListEveryParameterAtItsDefault) {
    std::vector<std::pair<FilterSpec, std::string>> all;
    for (const auto& f : filter_table()) all.emplace_back(f, CANONFORM_SCRIPTS_DIR);
    for (const auto& f : view_filter_table()) all.emplace_back(f, CANONFORM_VIEW_SCRIPTS_DIR);
    for (const auto& [f, dir] : all) {
        const std::string path = dir + "/" + f.script_file;
        std::ifstream in(path);
        ASSERT_TRUE(in) << path;
        std::stringstream ss;
        ss << in.rdbuf();
        EXPECT_EQ(ss.str(), default_script(f)) << path << " is out of date: regenerate it with canonform_mlx";
        for (const auto& p : f.params)
            EXPECT_NE(ss.str().find(std::string("name=\"") + p.name + "\""), std::string::npos) << p.name;
    }
}

// pymeshlab 2022.2 calls a filter by FilterPlugin::pythonFilterName() (the table's python_name),
// and also registers a deprecated name made from the menu name (lower case, spaces to '_'): no
// name may be taken twice, or pymeshlab's set of functions keeps only one of them.
TEST(FilterTable, PythonNamesForPymeshlab) {
    std::map<std::string, std::string> python;
    for (const auto& f : filter_table()) python[f.name] = f.python_name;
    for (const auto& f : view_filter_table()) python[f.name] = f.python_name;
    EXPECT_EQ(python, (std::map<std::string, std::string>{
                          {"Conformal factor", "compute_conformal_factor"},
                          {"Feature points", "compute_feature_points"},
                          {"Euclidean canonical form", "generate_euclidean_canonical_form"},
                          {"Geodesic canonical form", "generate_geodesic_canonical_form"},
                          {"Depth view descriptor", "compute_depth_view_descriptor"}}));
    std::set<std::string> all;
    for (const auto& [menu, name] : python) {
        std::string old = menu;
        for (char& c : old) c = c == ' ' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        EXPECT_TRUE(all.insert(name).second) << name;
        EXPECT_TRUE(all.insert(old).second) << old;
    }
}

TEST(FilterTable, ProseFoldsLineBreaksAndIndentationIntoOneSpace) {
    EXPECT_EQ(prose("Computes the\n                 conformal  factor.\n"), "Computes the conformal factor.");
    EXPECT_EQ(prose("\n  lead and trail \t\r\n"), "lead and trail");
    EXPECT_EQ(prose(""), "");
    for (const auto* t : {&filter_table(), &view_filter_table()})
        for (const auto& f : *t) {
            EXPECT_EQ(f.info.find("  "), std::string::npos) << f.name;
            EXPECT_EQ(f.info.find('\n'), std::string::npos) << f.name;
        }
}
