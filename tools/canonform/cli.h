// canonform tool: what every command shares - the command table's entry type, usage errors,
// progress on the terminal, JSON output and input checks.
//
// A command is a function that adds its CLI11 subcommand (options, defaults, help) and sets its
// callback; main.cpp lists them, one line each. Exit status: 0 ok, 1 bad input or failure (a
// message naming the problem on stderr), 2 usage error.
#pragma once

#include "canonform/common/errors.h"
#include "canonform/common/mesh.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace canonform::cli {


/// A usage error found after parsing (exit status 2, like CLI11's own).
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A progress line on stderr while stderr is a terminal ("[stage] 42%  12 s left"); empty otherwise.
ProgressFn terminal_progress(bool quiet, const std::string& label = "");

/// Prints `j` on stdout, one line.
void print_json(const nlohmann::ordered_json& j);

/// Validates the mesh read from `path` (InputError naming the file and the problem) and notes an
/// open surface on stderr unless `quiet`.
void validate_and_note(const std::string& path, const Mesh& m, bool quiet);

/// Runs fn(); an InputError it throws is re-thrown with the input's path in front.
template <class Fn>
auto on_input(const std::string& path, Fn fn) -> decltype(fn()) {
    try {
        return fn();
    } catch (const InputError& e) {
        const std::string what = e.what();
        if (what.find(path) != std::string::npos) throw;
        throw InputError("'" + path + "': " + what);
    }
}

/// The positional arguments IN (an input mesh) and OUT (`out_help`), both required.
void add_in_out(CLI::App* command, std::string& in, std::string& out, const std::string& out_help);

/// Seconds since `t0`.
double seconds_since(std::chrono::steady_clock::time_point t0);

/// "a,b,,c" -> {"a", "b", "c"}.
std::vector<std::string> split_list(const std::string& text);

/// A command: adds its subcommand (options, defaults, help, callback) to the app.
using AddCommand = void(CLI::App& app);

// The commands, in mesh_commands.cpp, views_commands.cpp and retrieval_commands.cpp.
AddCommand add_conformal, add_features, add_canonical, add_simplify, add_generate, add_picture,  // one mesh
    add_views, add_codebook, add_descriptor, add_distance,                                          // views
    add_retrieve, add_evaluate, add_grid;                                                            // retrieval

}  // namespace canonform::cli
