// SPDX-License-Identifier: GPL-3.0-or-later
// Any canonical-form method of the registry, by name and parameters, as `canonform canonical
// --method` and `canonform retrieve --method` take them.
//   example_method_by_name IN OUT [SPEC]      SPEC e.g. "euclidean-N:beta=65" or "geodesic-classical"
#include "canonform/canonical/method_registry.h"
#include "canonform/io/mesh_io.h"

#include <cstdio>
#include <exception>
#include <string>
#include <variant>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s IN OUT [METHOD[:KEY=VALUE...]]\n", argv[0]);
        return 2;
    }
    try {
        const canonform::Mesh mesh = canonform::io::read_mesh(argv[1]);
        const canonform::canonical::MethodSpec spec =
            canonform::canonical::parse_method_spec(argc > 3 ? argv[3] : "euclidean-N");

        const canonform::canonical::CanonicalForm form =
            spec.method().run(mesh.V, mesh.F, spec.settings(), {});
        canonform::io::write_mesh(argv[2], form.V, mesh.F, form.quality);

        std::printf("%s: %s\n", spec.to_string().c_str(), form.description.c_str());
        for (const auto& [key, value] : form.summary)  // what --json prints
            if (const double* d = std::get_if<double>(&value)) std::printf("  %s = %g\n", key.c_str(), *d);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
