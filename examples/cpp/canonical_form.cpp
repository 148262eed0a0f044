// SPDX-License-Identifier: GPL-3.0-or-later
// The Euclidean canonical form of a mesh file: read, compute, write.
//   example_canonical_form IN OUT [A|N]
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/io/mesh_io.h"

#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s IN OUT [A|N]\n", argv[0]);
        return 2;
    }
    try {
        const canonform::Mesh mesh = canonform::io::read_mesh(argv[1]);  // OFF, PLY, OBJ or STL

        canonform::canonical::EuclideanCanonicalFormOptions
            options;  // variant N, alpha 10, beta 130, ring 2, ...
        if (argc > 3 && std::string(argv[3]) == "A")
            options.variant = canonform::canonical::CanonicalVariant::A;

        const auto result = canonform::canonical::euclidean_canonical_form(mesh.V, mesh.F, options);
        // result.V: the form, same vertices and faces, in the input's units
        // result.phi: the normalised conformal factor; result.features: the feature points
        canonform::io::write_mesh(argv[2], result.V, mesh.F, result.phi);

        std::printf("%d feature points, %d SMACOF iterations, stress %.4g -> %.4g, %.3f s\n",
                    static_cast<int>(result.features.size()), result.iterations, result.initial_stress,
                    result.final_stress, result.seconds);
        return 0;
    } catch (const canonform::InputError& e) {  // the bad input, named
        std::fprintf(stderr, "bad input: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {  // NumericalError and the rest
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
