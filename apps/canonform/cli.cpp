// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli.h"

#include "canonform/io/mesh_io.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"

#ifdef _WIN32
#include <io.h>
#define isatty _isatty
#else
#include <unistd.h>
#endif

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace canonform::cli {

namespace {

// CANONFORM_PROGRESS_INTERVAL: seconds between two progress lines in a log (default 5; 0: every update).
double log_interval() {
    static const double interval = [] {
        const char* text = std::getenv("CANONFORM_PROGRESS_INTERVAL");
        if (!text || !*text) return ProgressLine::kLogInterval;
        char* end = nullptr;
        const double v = std::strtod(text, &end);
        if (*end || !(v >= 0 && v <= 86400)) {
            std::fprintf(stderr,
                         "canonform: note: CANONFORM_PROGRESS_INTERVAL='%s' is not a number of seconds in "
                         "[0, 86400]; using %g\n",
                         text, ProgressLine::kLogInterval);
            return ProgressLine::kLogInterval;
        }
        return v;
    }();
    return interval;
}

}  // namespace

ProgressLine::ProgressLine(bool quiet)
    : quiet_(quiet), terminal_(isatty(2) != 0), t0_(std::chrono::steady_clock::now()), last_(t0_) {}

void ProgressLine::update(const std::string& text, bool done) {
    if (quiet_) return;
    if (terminal_) {
        std::fprintf(stderr, "\r%-72s", text.c_str());
        if (done) std::fprintf(stderr, "\n");
        std::fflush(stderr);
        return;
    }
    // A log: whole lines, the first after the interval and then at most one per interval, and the
    // last one (if any was written, or the work took that long) - a short run writes nothing.
    const double interval = log_interval();
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_).count() < interval &&
        !(done && (written_ || seconds() >= interval)))
        return;
    std::fprintf(stderr, "%s\n", text.c_str());
    std::fflush(stderr);
    last_ = now;
    written_ = !done;
}

double ProgressLine::seconds() const {
    return seconds_since(t0_);
}

ProgressFn terminal_progress(bool quiet, const std::string& label) {
    const auto line = std::make_shared<ProgressLine>(quiet);
    return [line, label](double f, const char* stage) {
        const double el = line->seconds();
        const std::string what = label.empty() ? std::string(stage) : "[" + label + "] " + stage;
        char text[256];
        if (f > 0 && f < 1)
            std::snprintf(text, sizeof text, "%3d%%  %-40s %.0f s left", static_cast<int>(100 * f),
                          what.c_str(), el * (1 - f) / f);
        else
            std::snprintf(text, sizeof text, "%3d%%  %s", static_cast<int>(100 * f), what.c_str());
        line->update(text, f >= 1);
        return true;
    };
}

void print_json(const nlohmann::ordered_json& j) {
    std::cout << j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
}

void validate_and_note(const std::string& path, const Mesh& m, bool quiet) {
    const surface::MeshReport r = on_input(path, [&] { return surface::validate_mesh(m.V, m.F); });
    if (r.boundary_edges > 0 && !quiet)
        std::cerr << "canonform: note: '" << path << "' is open (" << r.boundary_edges
                  << " boundary edges); boundary curvature uses pi instead of 2 pi (eq. 8)\n";
}

Mesh read_input_mesh(const std::string& path, bool repair, bool quiet, bool validate) {
    Mesh m = io::read_mesh(path);
    if (repair) {
        const surface::MeshRepair r = on_input(path, [&] { return surface::repair_mesh(m.V, m.F); });
        std::cerr << "canonform: '" << path << "': " << r.summary() << "\n";
        m = r.mesh;
    }
    if (validate) validate_and_note(path, m, quiet);
    return m;
}

Mesh read_large_mesh(const std::string& path, bool repair, bool quiet) {
#if defined(__GLIBC__)
    constexpr int kOneGiB = 1 << 30;
    mallopt(M_MMAP_THRESHOLD, kOneGiB);  // blocks up to 1 GiB from the heap, reused once freed
    mallopt(M_TRIM_THRESHOLD, kOneGiB);  // the heap's free top is kept up to 1 GiB
#endif
    return read_input_mesh(path, repair, quiet);
}

void add_repair_flag(CLI::App* command, bool& repair) {
    const Parameter p = surface::repair_parameter();
    command->add_flag("--" + p.name(), repair, p.help() + " (one line on stderr)");
}

std::vector<std::pair<std::string, std::string>> ParameterArgs::given() const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string& name : order) {
        const CLI::Option* o = options.at(name);
        if (o->count() == 0) continue;
        const auto sw = switches.find(name);
        out.emplace_back(name, sw != switches.end() ? (sw->second ? "true" : "false") : values.at(name));
    }
    return out;
}

CLI::Option* add_parameter(CLI::App* c, const Parameter& p, ParameterArgs& args, const std::string& defaults,
                           bool check) {
    std::string flag = "--" + p.name();
    for (auto& ch : flag)
        if (ch == '_') ch = '-';
    // The default: CLI11 shows the option's ("=2"); a list of them (one per method) goes in the help.
    const std::string help = defaults.empty() ? p.help() : p.help() + " (default: " + defaults + ")";
    args.order.push_back(p.name());
    CLI::Option* o = nullptr;
    if (p.type() == ParameterType::Bool) {
        const bool on = p.truth(p.default_value());
        args.switches[p.name()] = on;
        std::string names = flag;
        if (on) {  // on by default: --NAME and --no-NAME (and the alias) turn it off
            names += ",!--no-" + flag.substr(2);
            if (!p.alias().empty()) names += ",!--" + p.alias();
        } else if (!p.alias().empty()) {
            names += ",--" + p.alias();
        }
        o = c->add_flag(names, args.switches[p.name()], help + (on ? " (on by default)" : ""));
    } else {
        if (!p.alias().empty()) flag = "--" + p.alias() + "," + flag;
        args.values[p.name()] = p.default_value();
        o = c->add_option(flag, args.values[p.name()], help)
                ->type_name(p.type() == ParameterType::Choice  ? "TEXT"
                            : p.type() == ParameterType::Int   ? "INT"
                            : p.type() == ParameterType::Float ? "FLOAT"
                                                               : "TEXT");
        if (!defaults.empty()) o->default_str("");
        if (check)
            o->check(CLI::Validator(
                [p](std::string& value) -> std::string {
                    try {
                        p.check(value);
                    } catch (const InputError& e) {
                        return e.what();
                    }
                    return "";
                },
                p.type() == ParameterType::Choice ? "{" +
                                                        [&p] {
                                                            std::string s;
                                                            for (const auto& ch : p.choices())
                                                                s += (s.empty() ? "" : ",") + ch;
                                                            return s;
                                                        }() +
                                                        "}"
                : p.is_number() ? (p.type() == ParameterType::Int ? "INT" : "NUMBER") + std::string(" in [") +
                                      format_number(p.min()) + ", " + format_number(p.max()) + "]"
                                : ""));
    }
    args.options[p.name()] = o;
    return o;
}

CLI::Validator mesh_output(bool faces) {
    return CLI::Validator(
        [faces](std::string& path) -> std::string {
            try {
                const io::MeshFormat f = io::output_mesh_format(path);
                if (!faces && f == io::MeshFormat::Stl)
                    return "cannot write '" + path +
                           "': an STL file cannot hold a point cloud (name it .ply, .off or .obj)";
            } catch (const std::exception& e) {
                return e.what();
            }
            return "";
        },
        "MESH FILE (.ply, .off, .obj, .stl)");
}

CLI::Validator finite_range(double min, double max) {
    std::ostringstream d;
    d << "NUMBER in [" << min << ", " << max << "]";
    return CLI::Validator(
        [min, max](std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !std::isfinite(v) || v < min || v > max) {
                std::ostringstream m;
                m << "value '" << text << "' is not a finite number in [" << min << ", " << max << "]";
                return m.str();
            }
            return "";
        },
        d.str());
}

void add_in_out(CLI::App* command, std::string& in, std::string& out, const std::string& out_help,
                bool mesh_out, bool faces) {
    command->add_option("IN", in, "input mesh (OFF, PLY, OBJ, STL)")->required();
    auto* o = command->add_option("OUT", out, out_help)->required();
    if (mesh_out) o->check(mesh_output(faces));
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
