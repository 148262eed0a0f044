// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the command-line tool on the same library as the MeshLab plugins, for batch work.
//
//   canonform COMMAND [ARGS] [OPTIONS]      canonform COMMAND --help: every option and default
//   canonform --version                     the version (CMakeLists.txt's project())
//
// Meshes in: OFF, PLY, OBJ or STL; meshes out: binary PLY, written atomically. Exit status: 0 ok,
// 1 bad input or failure (a message on stderr names the problem), 2 usage error.
//
// One or two programs from this file (apps/CMakeLists.txt). Where the whole tool links Qt, OpenCV
// or FAISS (with OpenBLAS and libgomp) - a Linux build from source - it is `canonform-full`, and
// `canonform` (built with CANONFORM_TOOL_LEAN) has only the commands that need the core and the
// views area (Eigen alone) - check, conformal, features, canonical, simplify, generate, descriptor,
// distance - and --version, and hands every other command to `canonform-full` beside it (execv,
// the same arguments), as well as `descriptor --sift opencv` (a command throws RunFull). So these
// commands start without loading those libraries, most of the whole tool's start-up
// (docs/benchmarks.md, "The tool's start-up and idle threads"); the others pay one lean start more.
// Elsewhere (the wheel, Windows) the whole tool links none of them and is `canonform` alone.
#include "cli.h"

#ifdef CANONFORM_HAVE_OPENCV_SIFT
#include "canonform/views/opencv_sift.h"
#endif
#include "canonform/common/heap_pages.h"
#include "canonform/common/version.h"

#include <cstring>
#include <iostream>
#ifdef CANONFORM_TOOL_LEAN
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <string>

#include <unistd.h>
#endif

namespace {

using namespace canonform::cli;

/// One command of the tool: its name and the function that adds it to the app.
struct Command {
    const char* name;
    AddCommand* add;
};

/// Every command, in the order of `canonform --help`. A new command: one line here (and in the
/// lean list too if it needs only the core and the views area).
#ifdef CANONFORM_TOOL_LEAN
const Command kCommands[] = {
    {"check", add_check},         {"conformal", add_conformal}, {"features", add_features},
    {"canonical", add_canonical}, {"simplify", add_simplify},   {"descriptor", add_descriptor},
    {"distance", add_distance},   {"generate", add_generate},
};
#else
const Command kCommands[] = {
    {"check", add_check},
    {"conformal", add_conformal},
    {"features", add_features},
    {"canonical", add_canonical},
    {"simplify", add_simplify},
    {"views", add_views},
    {"codebook", add_codebook},
    {"descriptor", add_descriptor},
    {"distance", add_distance},
    {"retrieve", add_retrieve},
    {"evaluate", add_evaluate},
    {"grid", add_grid},
    {"pr", add_pr},
    {"generate", add_generate},
    {"picture", add_picture},
    {"stage", add_stage},
    {"status", add_status},
    {"slurm", add_slurm},
    {"index", add_index},
    {"query", add_query},
};
#endif

bool known(const char* name) {
    for (const Command& c : kCommands)
        if (std::strcmp(c.name, name) == 0) return true;
    return false;
}

#ifdef CANONFORM_TOOL_LEAN
/// Runs `canonform-full`, the program beside this one, in place of this process with the same
/// arguments, for a command it alone has or for a call of a lean command that needs it (`needs`:
/// the options that do, RunFull). Returns only on failure (exit status 1; the message names the
/// program looked for).
///
/// First, unless the user has set them, the two settings that make the idle thread pools of the
/// whole tool's libraries sleep. OpenBLAS (linked through FAISS and OpenCV) starts its workers while
/// it is loaded, and by default each spins on sched_yield for 2^28 cycles (about 0.1 s) whenever it
/// waits for work - at start-up and after every BLAS call - which in a command without BLAS
/// (`descriptor`, ...) is CPU time thrown away. OPENBLAS_THREAD_TIMEOUT=4 (its smallest timeout,
/// 2^4 cycles) makes them sleep at once; the number of BLAS threads stays, so the codebook's k-means
/// keeps every core. OMP_WAIT_POLICY=PASSIVE does the same for libgomp's workers between parallel
/// regions. Both are read when the libraries are loaded, so they must be in the environment before
/// canonform-full starts. Results do not change.
int run_full(char** argv, const std::string& needs = "") {
    setenv("OPENBLAS_THREAD_TIMEOUT", "4", 0);
    setenv("OMP_WAIT_POLICY", "PASSIVE", 0);
    char self[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) {
        std::cerr << "canonform: cannot find the folder of this program, where canonform-full is "
                  << "(/proc/self/exe: " << std::strerror(errno) << ")\n";
        return 1;
    }
    std::string path(self, static_cast<size_t>(n));
    path = path.substr(0, path.find_last_of('/') + 1) + "canonform-full";
    execv(path.c_str(), argv);
    const int error = errno;
    if (error == ENOENT)
        std::cerr << "canonform: "
                  << (!needs.empty() ? "'" + std::string(argv[1]) + " " + needs + "' needs "
                      : argv[1]      ? "'" + std::string(argv[1]) + "' is a command of "
                                     : std::string())
                  << "canonform-full, which is missing (" << path
                  << "): install both programs of the tool (tools/install.sh)\n";
    else
        std::cerr << "canonform: cannot run " << path << ": " << std::strerror(error) << "\n";
    return 1;
}
#endif

}  // namespace

int main(int argc, char** argv) {
    canonform::advise_heap_huge_pages();  // a program, not a host's library: common/heap_pages.h
#ifdef CANONFORM_TOOL_LEAN
    // Everything but the lean commands and --version: the whole tool (its help lists every command).
    if (argc < 2 || (std::strcmp(argv[1], "--version") != 0 && !known(argv[1]))) return run_full(argv);
#endif
#ifdef CANONFORM_HAVE_OPENCV_SIFT
    canonform::views::register_opencv_sift();  // `--sift opencv` (the plugins carry only the built-in
                                               // extractor)
#endif
    CLI::App app{
        "canonform: pose-invariant canonical forms of non-rigid triangle meshes (Pickup et al. 2015) "
        "and view-based shape retrieval.\nMeshes: OFF, PLY, OBJ or STL in; binary PLY out. "
        "`canonform COMMAND --help` lists a command's options and defaults.",
        "canonform"};
    app.set_version_flag("--version", std::string("canonform ") + canonform::version());
    app.option_defaults()->always_capture_default();
    app.require_subcommand(1);
    for (const Command& c : kCommands) c.add(app);
    const char* command = argc > 1 ? argv[1] : "";
    if (argc > 1 && argv[1][0] != '-' && !known(argv[1])) {
        std::cerr << "canonform: unknown command '" << argv[1] << "'\n" << app.help();
        return 2;
    }
    try {
        app.parse(argc, argv);
        return 0;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "canonform" << (*command ? std::string(" ") + command : "") << ": " << e.what()
                  << "\n(`canonform" << (*command ? std::string(" ") + command : "")
                  << " --help` lists the options)\n";
        return 2;
    } catch (const ExitStatus& e) {
        return e.code;
#ifdef CANONFORM_TOOL_LEAN
    } catch (const RunFull& e) {
        return run_full(argv, e.what);
#endif
    } catch (const UsageError& e) {
        std::cerr << "canonform " << command << ": " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "canonform " << command << ": error: " << e.what() << "\n";
        return 1;
    }
}
