// SPDX-License-Identifier: GPL-3.0-or-later
// A program of another project: reads a mesh, computes a canonical form by any method of the
// registry with optional KEY=VALUE parameters, writes it (as `canonform canonical` does).
//   consumer IN OUT METHOD [KEY=VALUE...]
#include <canonform/canonical/euclidean_canonical_form.h>
#include <canonform/canonical/method_registry.h>
#include <canonform/io/mesh_io.h>

#include <iostream>

int main(int argc, char** argv) {
    if (argc < 4) {
        std::cerr << "usage: consumer IN OUT METHOD [KEY=VALUE...]\n";
        return 2;
    }
    try {
        std::string spec_text = argv[3];
        for (int k = 4; k < argc; ++k) spec_text += std::string(":") + argv[k];
        const canonform::canonical::MethodSpec spec = canonform::canonical::parse_method_spec(spec_text);
        const canonform::Mesh m = canonform::io::read_mesh(argv[1]);
        const canonform::canonical::CanonicalForm form = spec.method().run(m.V, m.F, spec.settings(), {});
        canonform::io::write_mesh(argv[2], form.V, m.F, form.quality);
        std::cout << spec.name << ": " << form.description << "\n";
        // The direct call of the library, for a user who wants one algorithm and its options.
        if (spec.name == "euclidean-N") {
            canonform::canonical::EuclideanCanonicalFormOptions o;
            o.smacof.max_iterations = 5;
            const auto r = canonform::canonical::euclidean_canonical_form(m.V, m.F, o);
            std::cout << "direct call: " << r.iterations << " iterations\n";
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "consumer: " << e.what() << "\n";
        return 1;
    }
}
