#include "cli.h"

#include "canonform/surface/mesh_topology.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

namespace canonform::cli {

ProgressFn terminal_progress(bool quiet, const std::string& label) {
    if (quiet || !isatty(2)) return {};
    const auto t0 = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
    return [t0, label](double f, const char* stage) {
        const double el = seconds_since(*t0);
        const std::string what = label.empty() ? std::string(stage) : "[" + label + "] " + stage;
        if (f > 0 && f < 1)
            std::fprintf(stderr, "\r%3d%%  %-40s %.0f s left   ", static_cast<int>(100 * f), what.c_str(),
                         el * (1 - f) / f);
        else
            std::fprintf(stderr, "\r%3d%%  %-40s                ", static_cast<int>(100 * f), what.c_str());
        if (f >= 1) std::fprintf(stderr, "\n");
        return true;
    };
}

void print_json(const nlohmann::ordered_json& j) { std::cout << j.dump() << "\n"; }

void validate_and_note(const std::string& path, const Mesh& m, bool quiet) {
    const MeshReport r = on_input(path, [&] { return validate_mesh(m.V, m.F); });
    if (r.boundary_edges > 0 && !quiet)
        std::cerr << "canonform: note: '" << path << "' is open (" << r.boundary_edges
                  << " boundary edges); boundary curvature uses pi instead of 2 pi (eq. 8)\n";
}

void add_in_out(CLI::App* command, std::string& in, std::string& out, const std::string& out_help) {
    command->add_option("IN", in, "input mesh (OFF, PLY, OBJ, STL)")->required();
    command->add_option("OUT", out, out_help)->required();
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream s(text);
    for (std::string item; std::getline(s, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

}  // namespace canonform::cli
