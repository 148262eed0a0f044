#include "filter_table.h"
#include "view_filter_table.h"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

using namespace canonform::plugin;

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
