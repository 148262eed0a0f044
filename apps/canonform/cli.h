// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: what every command shares - the command table's entry type, usage errors,
// progress on the terminal, JSON output and input checks.
//
// A command is a function that adds its CLI11 subcommand (options, defaults, help) and sets its
// callback; main.cpp lists them, one line each. Exit status: 0 ok, 1 bad input or failure (a
// message naming the problem on stderr), 2 usage error.
#pragma once

#include "canonform/common/errors.h"
#include "canonform/common/mesh.h"
#include "canonform/common/parameters.h"

#include "canonform/retrieval/experiment.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace canonform::cli {

/// A usage error found after parsing (exit status 2, like CLI11's own).
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Ends a command with this exit status after it has said why itself (e.g. `check` finding problems).
struct ExitStatus {
    int code;
};

/// Thrown by a command of the lean program (CANONFORM_TOOL_LEAN, main.cpp), before any work, for a
/// call that needs a library only canonform-full links (`descriptor --sift opencv`): main() then
/// runs canonform-full with the same arguments. `what`: the options that need it ("--sift opencv").
struct RunFull {
    std::string what;
};

/// Progress on stderr. On a terminal, one line rewritten in place; otherwise (a log file, a pipe)
/// one whole line per update, at most one every kLogInterval seconds (CANONFORM_PROGRESS_INTERVAL
/// overrides it; 0: every update), and the last one if any was written or the work took that long
/// (so a short run writes nothing to a log).
class ProgressLine {
public:
    static constexpr double kLogInterval = 5.0;
    explicit ProgressLine(bool quiet);
    /// Shows `text`; `done` marks the last update.
    void update(const std::string& text, bool done);
    /// Seconds since construction.
    double seconds() const;

private:
    bool quiet_, terminal_, written_ = false;
    std::chrono::steady_clock::time_point t0_, last_;
};

/// Progress of a library call as ProgressLine updates ("42%  [label] stage  12 s left").
ProgressFn terminal_progress(bool quiet, const std::string& label = "");

/// Prints `j` on stdout, one line (invalid UTF-8 in a string, e.g. a class name, is replaced by
/// U+FFFD: the output is always valid JSON).
void print_json(const nlohmann::ordered_json& j);

/// Validates the mesh read from `path` (InputError naming the file and the problem) and notes an
/// open surface on stderr unless `quiet`.
void validate_and_note(const std::string& path, const Mesh& m, bool quiet);

/// Reads the input mesh `path`; with `repair`, repairs it (surface/mesh_repair.h) and prints the
/// repair's one-line summary on stderr (always: what changed is never silent); then, if
/// `validate`, validates it as validate_and_note() (the view commands leave that to
/// compute_views(), which accepts several components).
Mesh read_input_mesh(const std::string& path, bool repair, bool quiet, bool validate = true);

/// read_input_mesh() for the commands that work on one large mesh (conformal, features, canonical),
/// which first makes freed memory stay with the process for reuse instead of going back to the
/// system (glibc's malloc returns large blocks with munmap, and they are faulted in again at their
/// next use; the figures are in docs/benchmarks.md, "Canonical form at scale"). The peak stays the peak of
/// the live data.
Mesh read_large_mesh(const std::string& path, bool repair, bool quiet);

/// Adds --repair (surface/mesh_repair.h's repair_parameter(); default off: strict) to a command
/// that reads meshes.
void add_repair_flag(CLI::App* command, bool& repair);

/// The texts given on the command line for parameters (common/parameters.h), by add_parameter().
struct ParameterArgs {
    std::map<std::string, std::string> values;    ///< name -> text (the default until given)
    std::map<std::string, bool> switches;         ///< name -> value, for a switch
    std::map<std::string, CLI::Option*> options;  ///< name -> its option
    std::vector<std::string> order;               ///< names, in the order added
    /// The parameters given on the command line, in the order added: (name, text).
    std::vector<std::pair<std::string, std::string>> given() const;
};

/// Adds the option of parameter `p` to a command, derived from its definition: --NAME (underscores
/// as dashes) and --ALIAS; a switch is a flag (--NAME, or when it is on by default --no-NAME, and
/// its alias, which turn it off). The help is the parameter's, with `defaults` (default: its
/// default value); with `check`, a value the parameter refuses is a usage error naming it.
CLI::Option* add_parameter(CLI::App* command, const Parameter& p, ParameterArgs& args,
                           const std::string& defaults = "", bool check = true);

/// The options of a ParameterSet's parameters, and the options read back from what was given
/// (a usage error names a bad value).
template <class Options>
void add_parameters(CLI::App* command, const ParameterSet<Options>& set, ParameterArgs& args) {
    for (const Parameter& p : set.parameters()) add_parameter(command, p, args);
}
template <class Options>
Options read_parameters(const ParameterSet<Options>& set, const ParameterArgs& args) {
    try {
        return set.read(args.given());
    } catch (const InputError& e) {
        throw UsageError(e.what());
    }
}

/// A validator of an output mesh name: .ply, .off, .obj, .stl or none (PLY); `faces` false for a
/// point cloud (not .stl). A usage error (exit 2) before any work.
CLI::Validator mesh_output(bool faces = true);

/// A validator of a number in [min, max] that refuses NaN and infinities (CLI11's Range lets NaN
/// through); its message names the option's value.
CLI::Validator finite_range(double min, double max);

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

/// The positional arguments IN (an input mesh) and OUT (`out_help`), both required; OUT is checked
/// by mesh_output(faces) when `mesh_out` (a mesh file), else left to the command.
void add_in_out(CLI::App* command, std::string& in, std::string& out, const std::string& out_help,
                bool mesh_out = true, bool faces = true);

/// Seconds since `t0`.
double seconds_since(std::chrono::steady_clock::time_point t0);

/// "a,b,,c" -> {"a", "b", "c"}.
std::vector<std::string> split_list(const std::string& text);

/// The options of a retrieval run that `retrieve`, `stage init` and `slurm` share (dataset, labels,
/// out, method, words, codebook, codebook-sample, simplify, noise, seed, sift, repair), written as
/// text into `methods` and `sift` and read by finish_experiment_options().
struct ExperimentArgs {
    retrieval::ExperimentOptions o;
    std::string methods = "none,euclidean-N";
    ParameterArgs sift;  ///< --sift (views/view_parameters.h)
};
void add_experiment_options(CLI::App* command, ExperimentArgs& args);
/// The options parsed: labels default, SIFT backend, codebook method or file, methods (fused ones
/// only if `fused`, else a usage error).
retrieval::ExperimentOptions finish_experiment_options(const ExperimentArgs& args, bool fused);

/// A command: adds its subcommand (options, defaults, help, callback) to the app.
using AddCommand = void(CLI::App& app);

// The commands, in mesh_commands.cpp, picture_command.cpp, views_commands.cpp,
// descriptor_commands.cpp, retrieval_commands.cpp and sharded_commands.cpp.
AddCommand add_check, add_conformal, add_features, add_canonical, add_simplify, add_generate,
    add_picture,                                             // one mesh
    add_views, add_codebook, add_descriptor, add_distance,   // views
    add_retrieve, add_evaluate, add_grid, add_pr,            // retrieval
    add_stage, add_status, add_slurm, add_index, add_query;  // sharded_commands.cpp

}  // namespace canonform::cli
