// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the `picture` command (apart from the other one-mesh commands, which the lean
// front binary carries without Qt: main.cpp).
#include "cli.h"
#include "picture.h"

#include "canonform/io/mesh_io.h"

#include <memory>

namespace canonform::cli {

void add_picture(CLI::App& app) {
    struct Args {
        std::string out, mesh, points, canonical;
        int size = 420;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("picture", "a picture of a mesh, its feature points and its canonical form");
    c->add_option("OUT", a->out, "output PNG")->required();
    c->add_option("MESH", a->mesh, "the mesh (PLY quality: its colour)")->required();
    c->add_option("--points", a->points, "feature points (a point cloud file)");
    c->add_option("--canonical", a->canonical, "canonical form (same vertex order as MESH)");
    c->add_option("--size", a->size, "pixels per panel")->check(CLI::Range(64, 4096));
    c->callback([a] {
        PictureInputs in;
        io::MeshFile f = io::read_mesh_file(a->mesh);
        in.mesh = std::move(f.mesh);
        in.mesh_quality = std::move(f.quality);
        check_drawable(a->mesh, in.mesh, in.mesh_quality);
        if (!a->points.empty()) {
            in.points = io::read_mesh(a->points).V;
            check_points(a->points, in.points);
        }
        if (!a->canonical.empty()) {
            f = io::read_mesh_file(a->canonical);
            in.canonical = std::move(f.mesh);
            in.canonical_quality = std::move(f.quality);
            check_drawable(a->canonical, in.canonical, in.canonical_quality);
            if (in.canonical.V.rows() != in.mesh.V.rows())
                throw InputError("'" + a->canonical + "' has " + std::to_string(in.canonical.V.rows()) +
                                 " vertices, the mesh '" + a->mesh + "' " + std::to_string(in.mesh.V.rows()) +
                                 ": a canonical form keeps the vertices of its mesh");
        }
        write_picture(a->out, in, a->size);
    });
}

}  // namespace canonform::cli
