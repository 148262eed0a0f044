// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the command-line tool on the same library as the MeshLab plugins, for batch work.
//
//   canonform COMMAND [ARGS] [OPTIONS]      canonform COMMAND --help: every option and default
//   canonform --version                     the version (CMakeLists.txt's project())
//
// Meshes in: OFF, PLY, OBJ or STL; meshes out: binary PLY, written atomically. Exit status: 0 ok,
// 1 bad input or failure (a message on stderr names the problem), 2 usage error.
#include "cli.h"

#ifdef CANONFORM_HAVE_OPENCV_SIFT
#include "canonform/views/opencv_sift.h"
#endif
#include "canonform/common/version.h"

#include <cstring>
#include <iostream>

namespace {

using namespace canonform::cli;

/// One command of the tool: its name and the function that adds it to the app.
struct Command {
    const char* name;
    AddCommand* add;
};

/// Every command, in the order of `canonform --help`. A new command: one line here.
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

bool known(const char* name) {
    for (const Command& c : kCommands)
        if (std::strcmp(c.name, name) == 0) return true;
    return false;
}

}  // namespace

int main(int argc, char** argv) {
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
    } catch (const UsageError& e) {
        std::cerr << "canonform " << command << ": " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "canonform " << command << ": error: " << e.what() << "\n";
        return 1;
    }
}
