/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A C program of another project using the installed C API (canonform::c_api, docs/library.md):
 * reads a mesh, computes a canonical form by any method of the registry with optional KEY=VALUE
 * parameters, writes it (as `canonform canonical` does).
 *   c_consumer IN OUT METHOD [KEY=VALUE...] */
#include <canonform/c_api/canonform.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char** argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: c_consumer IN OUT METHOD [KEY=VALUE...]\n");
        return 2;
    }
    enum { MAX = 16 };
    const char* keys[MAX];
    const char* values[MAX];
    int n = 0;
    for (int k = 4; k < argc && n < MAX; ++k) {
        char* eq = strchr(argv[k], '=');
        if (!eq) {
            fprintf(stderr, "c_consumer: %s is not KEY=VALUE\n", argv[k]);
            return 2;
        }
        *eq = '\0';
        keys[n] = argv[k];
        values[n++] = eq + 1;
    }
    canonform_array *V = NULL, *F = NULL;
    int s = canonform_read_mesh(argv[1], &V, &F, NULL);
    if (s == CANONFORM_OK) {
        double* Y = (double*)malloc(sizeof(double) * (size_t)(V->shape[0] * 3));
        char* info = NULL;
        canonform_array* q =
            NULL; /* the conformal factor, where the method has one: the tool writes it too */
        s = canonform_canonical_form((const double*)V->data, V->shape[0], (const int32_t*)F->data,
                                     F->shape[0], argv[3], keys, values, n, 0, NULL, NULL, Y, &q, &info);
        if (s == CANONFORM_OK)
            s = canonform_write_mesh(argv[2], Y, V->shape[0], (const int32_t*)F->data, F->shape[0],
                                     q->shape[0] ? (const double*)q->data : NULL);
        canonform_array_free(q);
        if (s == CANONFORM_OK)
            printf("canonform %s (C API %d): %s\n", canonform_version(), canonform_api_version(), info);
        canonform_free(info);
        free(Y);
    }
    canonform_array_free(V);
    canonform_array_free(F);
    /* a call of an area this build may leave out: OK, or UNSUPPORTED saying so */
    canonform_array* D = NULL;
    int views = canonform_read_distance_matrix("no-such-file.bin", &D);
    printf("retrieval area: %s\n", views == CANONFORM_UNSUPPORTED ? "not in this build" : "in this build");
    if (s != CANONFORM_OK) {
        fprintf(stderr, "c_consumer: %s: %s\n", canonform_status_name(s), canonform_last_error());
        return 1;
    }
    return 0;
}
