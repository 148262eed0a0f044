/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The C API (src/canonform/c_api/canonform.h) from a program compiled as C (C99): every kind of
 * function, its status codes and messages, caller-owned and library arrays, text outputs, progress
 * and cancelling, a log callback that stops a run. ctest c_api.test runs it (tests/c_api/run_test.sh):
 *
 *   c_api_test WORK_DIR [MESH FORM]
 *
 * WORK_DIR: a writable folder (files are written there). MESH, FORM: a mesh and the form
 * `canonform canonical MESH FORM` wrote: the C API's form of MESH must be the same doubles.
 * Prints one "ok"/"FAIL" line per check and "N passed, M failed"; exit status 1 on any failure.
 */
#include <canonform/c_api/canonform.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int passed = 0, failed = 0;

static void check(int ok, const char* what) {
    printf("%s %s\n", ok ? "ok  " : "FAIL", what);
    if (ok)
        ++passed;
    else
        ++failed;
}

/* A call that must fail with `status` and a message containing `needle`. */
static void check_error(int got, int status, const char* needle, const char* what) {
    const char* message = canonform_last_error();
    int ok = got == status && strstr(message, needle) != NULL;
    if (!ok) printf("     got %s: %s\n", canonform_status_name(got), message);
    check(ok, what);
}

static char* join(const char* dir, const char* name) {
    size_t n = strlen(dir) + strlen(name) + 2;
    char* p = (char*)malloc(n);
    snprintf(p, n, "%s/%s", dir, name);
    return p;
}

typedef struct {
    int calls;
    double last;
    int monotone;
    int saw_smacof;
    const char* stop_at; /* cancel at the first stage containing this (NULL: never) */
} Progress;

static int on_progress(void* user, double fraction, const char* stage) {
    Progress* p = (Progress*)user;
    if (fraction < p->last) p->monotone = 0;
    p->last = fraction;
    ++p->calls;
    if (strstr(stage, "SMACOF")) p->saw_smacof = 1;
    return !(p->stop_at && strstr(stage, p->stop_at));
}

static int stop_logging(void* user, const char* line) {
    (void)line;
    ++*(int*)user;
    return 0;
}

int main(int argc, char** argv) {
    if (argc != 2 && argc != 4) {
        fprintf(stderr, "usage: c_api_test WORK_DIR [MESH FORM]\n");
        return 2;
    }
    const char* work = argv[1];

    /* version */
    check(canonform_api_version() == CANONFORM_C_API_VERSION, "canonform_api_version() is the header's");
    check(strlen(canonform_version()) >= 5 && strchr(canonform_version(), '.') != NULL,
          "canonform_version() is MAJOR.MINOR.PATCH");
    check(strcmp(canonform_status_name(CANONFORM_CANCELLED), "CANONFORM_CANCELLED") == 0, "status names");

    /* a figure, written and read back */
    canonform_array *V = NULL, *F = NULL, *V2 = NULL, *F2 = NULL, *q = NULL;
    check(canonform_figure(1200, 2, "standard", &V, &F) == CANONFORM_OK && V->type == CANONFORM_FLOAT64 &&
              F->type == CANONFORM_INT32 && V->shape[0] >= 1000 && V->shape[1] == 3 && F->shape[1] == 3,
          "canonform_figure gives FLOAT64 (n, 3) and INT32 (m, 3)");
    const int64_t nv = V->shape[0], nf = F->shape[0];
    const double* v = (const double*)V->data;
    const int32_t* f = (const int32_t*)F->data;
    char* ply = join(work, "figure.ply");
    check(canonform_write_mesh(ply, v, nv, f, nf, NULL) == CANONFORM_OK, "canonform_write_mesh writes a PLY");
    check(canonform_read_mesh(ply, &V2, &F2, &q) == CANONFORM_OK && V2->shape[0] == nv &&
              F2->shape[0] == nf && memcmp(V2->data, v, sizeof(double) * (size_t)(nv * 3)) == 0 &&
              memcmp(F2->data, f, sizeof(int32_t) * (size_t)(nf * 3)) == 0 && q->ndim == 1 &&
              q->shape[0] == 0,
          "canonform_read_mesh gives the same arrays back, no quality");
    canonform_array_free(V2);
    canonform_array_free(F2);
    canonform_array_free(q);

    /* errors: a status, the library's message, NULL outputs */
    char* missing = join(work, "missing.off");
    V2 = (canonform_array*)1;
    check_error(canonform_read_mesh(missing, &V2, &F2, NULL), CANONFORM_INPUT_ERROR, "missing.off",
                "a missing file is INPUT_ERROR naming it");
    check(V2 == NULL && F2 == NULL, "... and the output pointers are NULL");
    check_error(canonform_figure(10, 0, NULL, &V2, &F2), CANONFORM_INPUT_ERROR,
                "vertices must be between 500 and 2000000, got 10",
                "an option out of range names it and its range");
    check_error(canonform_read_mesh(NULL, &V2, &F2, NULL), CANONFORM_INPUT_ERROR, "path",
                "a NULL path is INPUT_ERROR");

    /* the canonical form, with progress and the JSON summary */
    double* Y = (double*)malloc(sizeof(double) * (size_t)(nv * 3));
    char* info = NULL;
    Progress p = {0, 0.0, 1, 0, NULL};
    canonform_array* quality = NULL;
    int s = canonform_canonical_form(v, nv, f, nf, "euclidean-N", NULL, NULL, 0, 1, on_progress, &p, Y,
                                     &quality, &info);
    check(s == CANONFORM_OK, "canonform_canonical_form euclidean-N");
    check(quality && quality->type == CANONFORM_FLOAT64 && quality->ndim == 1 && quality->shape[0] == nv,
          "... its quality: the conformal factor, one value per vertex");
    canonform_array_free(quality);
    check(info && strstr(info, "\"vertices\":") && strstr(info, "\"iterations\":"),
          "... its JSON summary has vertices and iterations");
    check(p.calls >= 5 && p.monotone && p.last == 1.0 && p.saw_smacof,
          "... progress: increasing fractions up to 1, a SMACOF stage");
    int finite = 1, moved = 0;
    for (int64_t k = 0; k < nv * 3; ++k) {
        if (!isfinite(Y[k])) finite = 0;
        if (Y[k] != v[k]) moved = 1;
    }
    check(finite && moved, "... the form is finite and not the mesh");
    canonform_free(info);

    const char* keys[] = {"beta", "acceleration"};
    const char* values[] = {"65", "none"};
    double* Y2 = (double*)malloc(sizeof(double) * (size_t)(nv * 3));
    check(canonform_canonical_form(v, nv, f, nf, "euclidean-A", keys, values, 2, 0, NULL, NULL, Y2, NULL,
                                   NULL) == CANONFORM_OK,
          "parameters by name (beta=65, acceleration=none), no progress, no summary");
    const char* bad_values[] = {"-1"};
    check_error(canonform_canonical_form(v, nv, f, nf, "euclidean-N", keys, bad_values, 1, 0, NULL, NULL, Y2,
                                         NULL, NULL),
                CANONFORM_INPUT_ERROR, "beta", "a parameter out of range is INPUT_ERROR naming it");
    check_error(
        canonform_canonical_form(v, nv, f, nf, "euclidean-Q", NULL, NULL, 0, 0, NULL, NULL, Y2, NULL, NULL),
        CANONFORM_INPUT_ERROR, "unknown method 'euclidean-Q'",
        "an unknown method is INPUT_ERROR listing the methods");
    check_error(canonform_canonical_form(v, nv, f, nf, NULL, NULL, NULL, 0, -1, NULL, NULL, Y2, NULL, NULL),
                CANONFORM_INPUT_ERROR, "threads", "threads -1 is INPUT_ERROR");
    Progress stop = {0, 0.0, 1, 0, "SMACOF"};
    check_error(
        canonform_canonical_form(v, nv, f, nf, NULL, NULL, NULL, 0, 1, on_progress, &stop, Y2, NULL, NULL),
        CANONFORM_CANCELLED, "cancelled by the user", "a progress function returning 0 cancels (CANCELLED)");
    double* bad = (double*)malloc(sizeof(double) * (size_t)(nv * 3));
    memcpy(bad, v, sizeof(double) * (size_t)(nv * 3));
    bad[0] = NAN;
    check_error(canonform_canonical_form(bad, nv, f, nf, NULL, NULL, NULL, 0, 0, NULL, NULL, Y2, NULL, NULL),
                CANONFORM_INPUT_ERROR, "NaN", "a NaN coordinate is INPUT_ERROR (the library's validation)");
    check_error(canonform_canonical_form(v, nv, f, 0, NULL, NULL, NULL, 0, 0, NULL, NULL, Y2, NULL, NULL),
                CANONFORM_INPUT_ERROR, "no faces", "a point cloud is INPUT_ERROR");
    check_error(canonform_canonical_form(NULL, 5, f, nf, NULL, NULL, NULL, 0, 0, NULL, NULL, Y2, NULL, NULL),
                CANONFORM_INPUT_ERROR, "NULL", "a NULL array with rows is INPUT_ERROR");
    char* methods = NULL;
    check(canonform_methods_json(&methods) == CANONFORM_OK && strstr(methods, "\"name\":\"euclidean-N\"") &&
              strstr(methods, "\"parameters\":["),
          "canonform_methods_json lists the registry");
    canonform_free(methods);

    /* conformal factor, feature points, repair, simplify */
    double* phi = (double*)malloc(sizeof(double) * (size_t)nv);
    int in01 = canonform_conformal_factor(v, nv, f, nf, 1, NULL, NULL, phi) == CANONFORM_OK;
    double lo = 1, hi = 0;
    for (int64_t k = 0; k < nv; ++k) {
        lo = phi[k] < lo ? phi[k] : lo;
        hi = phi[k] > hi ? phi[k] : hi;
    }
    check(in01 && lo == 0.0 && hi == 1.0, "canonform_conformal_factor normalised spans [0, 1]");
    canonform_array* idx = NULL;
    check(canonform_feature_points(v, nv, f, nf, 2, "none", 0, NULL, NULL, &idx) == CANONFORM_OK &&
              idx->type == CANONFORM_INT64 && idx->shape[0] > 0 &&
              idx->shape[0] <= (int64_t)ceil(sqrt((double)nv)) && phi[((int64_t*)idx->data)[0]] == 1.0,
          "canonform_feature_points: at most ceil(sqrt(n)), the first at phi's maximum");
    canonform_array_free(idx);
    check_error(canonform_feature_points(v, nv, f, nf, 0, NULL, 0, NULL, NULL, &idx), CANONFORM_INPUT_ERROR,
                "ring", "ring 0 is INPUT_ERROR");
    int32_t* dup = (int32_t*)malloc(sizeof(int32_t) * (size_t)((nf + 1) * 3));
    memcpy(dup, f, sizeof(int32_t) * (size_t)(nf * 3));
    memcpy(dup + nf * 3, f, sizeof(int32_t) * 3);
    char* summary = NULL;
    check(canonform_repair_mesh(v, nv, dup, nf + 1, &V2, &F2, &summary) == CANONFORM_OK &&
              F2->shape[0] == nf && strstr(summary, "1 duplicate face"),
          "canonform_repair_mesh removes a duplicate face and says so");
    canonform_array_free(V2);
    canonform_array_free(F2);
    canonform_free(summary);
    s = canonform_simplify(v, nv, f, nf, 500, &V2, &F2);
    check(s == CANONFORM_UNSUPPORTED || (s == CANONFORM_OK && V2->shape[0] <= 520 && V2->shape[0] >= 480),
          "canonform_simplify to about 500 vertices (or UNSUPPORTED in a core-only build)");
    int retrieval = s == CANONFORM_OK;
    canonform_array_free(V2);
    canonform_array_free(F2);

    /* views: raw features, a codebook, histograms, distances */
    canonform_array *feat = NULL, *counts = NULL, *words = NULL, *hist = NULL, *counts2 = NULL;
    s = canonform_view_descriptor(v, nv, f, nf, NULL, 0, NULL, NULL, 128, 0, &feat, &counts);
    if (s == CANONFORM_UNSUPPORTED) {
        check(strlen(canonform_sift_backends()) == 0, "no views area: no SIFT extractor listed");
    } else {
        int64_t total = 0;
        for (int k = 0; k < 66 && s == CANONFORM_OK; ++k) total += ((int64_t*)counts->data)[k];
        check(s == CANONFORM_OK && feat->type == CANONFORM_FLOAT32 && feat->shape[1] == 128 &&
                  counts->shape[0] == 66 && total == feat->shape[0] && total > 40,
              "canonform_view_descriptor: stacked features, 66 counts that add up");
        check(canonform_sift_backend_available(canonform_default_sift()) == 1 &&
                  strstr(canonform_sift_backends(), "canonform") &&
                  canonform_sift_backend_available("surf") == 0,
              "the default extractor is available");
        check_error(canonform_view_descriptor(v, nv, f, nf, NULL, 0, NULL, "surf", 128, 0, &hist, &counts2),
                    CANONFORM_INPUT_ERROR, "surf", "an unknown extractor is INPUT_ERROR naming it");
        check(canonform_train_codebook((const float*)feat->data, feat->shape[0], 16, 0, 0, "lloyd", &words) ==
                      CANONFORM_OK &&
                  words->shape[0] == 16 && words->shape[1] == 128,
              "canonform_train_codebook (lloyd): FLOAT32 (16, 128)");
        char* cbpath = join(work, "codebook.bin");
        canonform_array* loaded = NULL;
        check(canonform_save_codebook(cbpath, (const float*)words->data, 16) == CANONFORM_OK &&
                  canonform_load_codebook(cbpath, &loaded) == CANONFORM_OK &&
                  memcmp(loaded->data, words->data, sizeof(float) * 16 * 128) == 0,
              "a codebook saved and loaded is the same words");
        canonform_array_free(loaded);
        s = canonform_view_descriptor(v, nv, f, nf, NULL, 0, cbpath, NULL, 128, 0, &hist, &counts2);
        int sums = s == CANONFORM_OK && hist->shape[0] == 66 && hist->shape[1] == 16;
        for (int k = 0; k < 66 && sums; ++k) {
            float t = 0;
            for (int w = 0; w < 16; ++w) t += ((float*)hist->data)[k * 16 + w];
            if (t != (float)((int64_t*)counts2->data)[k]) sums = 0;
        }
        check(sums, "with a codebook file: (66, 16) histograms whose sums are the keypoint counts");
        double* dense = (double*)malloc(sizeof(double) * 66 * 16);
        for (int k = 0; k < 66 * 16; ++k) dense[k] = ((float*)hist->data)[k];
        double d = -1;
        check(canonform_clock_distance(dense, 66, 16, dense, 66, 16, &d) == CANONFORM_OK && d == 0.0,
              "canonform_clock_distance of a descriptor to itself is 0");
        check_error(canonform_clock_distance(dense, 66, 16, dense, 65, 16, &d), CANONFORM_INPUT_ERROR,
                    "different view counts", "descriptors of different view counts are INPUT_ERROR");
        double* other = (double*)malloc(sizeof(double) * 66 * 16);
        for (int k = 0; k < 66 * 16; ++k) other[k] = dense[(k + 16) % (66 * 16)];
        const double* models[] = {dense, other, dense};
        const int64_t views[] = {66, 66, 66}, nwords[] = {16, 16, 16};
        float D[9];
        Progress dp = {0, 0.0, 1, 0, NULL};
        check(canonform_distance_matrix(models, views, nwords, 3, 0, on_progress, &dp, D) == CANONFORM_OK &&
                  D[0] == 0 && D[1] == D[3] && D[1] > 0 && D[2] == 0 && dp.last == 1.0,
              "canonform_distance_matrix: symmetric, zero diagonal, progress to 1");
        free(dense);
        free(other);
        free(cbpath);
    }
    canonform_array_free(feat);
    canonform_array_free(counts);
    canonform_array_free(words);
    canonform_array_free(hist);
    canonform_array_free(counts2);

    /* retrieval: measures, and a run stopped by its log callback */
    if (retrieval) {
        const double Dm[36] = {0, 1, 1, 2, 2, 2, 1, 0, 1, 2, 2, 2, 1, 1, 0, 2, 2, 2,
                               2, 2, 2, 0, 1, 1, 2, 2, 2, 1, 0, 1, 2, 2, 2, 1, 1, 0};
        const char* labels[] = {"cat", "cat", "cat", "dog", "dog", "dog"};
        char* json = NULL;
        check(canonform_evaluate(Dm, 6, 6, NULL, labels, 6, NULL, &json) == CANONFORM_OK &&
                  strstr(json, "\"nn\":1.0") && strstr(json, "\"first_tier\":1.0"),
              "canonform_evaluate of a perfect matrix: NN and first tier 1");
        canonform_free(json);
        check_error(canonform_evaluate(Dm, 6, 6, NULL, labels, 5, NULL, &json), CANONFORM_INPUT_ERROR, "5",
                    "fewer labels than rows is INPUT_ERROR");
        canonform_retrieve_options o;
        canonform_retrieve_options_init(&o);
        check(o.words == 1500 && strcmp(o.methods, "none,euclidean-N") == 0 && o.codebook_sample > 0,
              "retrieve options' defaults");
        o.dataset = work;
        o.out = work;
        char* missing_labels = join(work, "missing.csv");
        o.labels = missing_labels;
        check_error(canonform_retrieve(&o, NULL, NULL, NULL, NULL, &json), CANONFORM_INPUT_ERROR,
                    "missing.csv", "canonform_retrieve with a missing labels file is INPUT_ERROR naming it");
        free(missing_labels);
        o.words = 0;
        check_error(canonform_retrieve(&o, NULL, NULL, NULL, NULL, &json), CANONFORM_INPUT_ERROR,
                    "words must be between 1 and 1000000", "canonform_retrieve checks its options first");
        /* a collection of three figures: one named twice is refused before any work; the run of
           three distinct ones is stopped by its log callback at the first line */
        char* coll = join(work, "labels.csv");
        FILE* lf = fopen(coll, "w");
        fprintf(lf, "path,class\nfigure.ply,a\nfigure.ply,a\nfigure.ply,a\n");
        fclose(lf);
        o.words = 8;
        o.labels = coll;
        o.methods = "none";
        o.codebook = "lloyd";
        char* run = join(work, "run");
        o.out = run;
        int lines = 0;
        check_error(canonform_retrieve(&o, NULL, NULL, stop_logging, &lines, &json), CANONFORM_INPUT_ERROR,
                    "two models are named", "a collection naming one mesh twice is refused before any work");
        check(lines == 0, "... without a log line");
        for (int k = 1; k <= 2; ++k) {
            canonform_array *PV = NULL, *PF = NULL;
            char name[32];
            snprintf(name, sizeof name, "pose%d.ply", k);
            char* path = join(work, name);
            canonform_figure(600, k, NULL, &PV, &PF);
            canonform_write_mesh(path, (const double*)PV->data, PV->shape[0], (const int32_t*)PF->data,
                                 PF->shape[0], NULL);
            canonform_array_free(PV);
            canonform_array_free(PF);
            free(path);
        }
        lf = fopen(coll, "w");
        fprintf(lf, "path,class\nfigure.ply,a\npose1.ply,a\npose2.ply,a\n");
        fclose(lf);
        check_error(canonform_retrieve(&o, NULL, NULL, stop_logging, &lines, &json), CANONFORM_CANCELLED,
                    "cancelled", "a log callback returning 0 stops the run (CANCELLED)");
        check(lines == 1 && json == NULL, "... at its first line, with no result");
        free(coll);
        free(run);
    }

    /* the tool's form of a given mesh, to the bit */
    if (argc == 4) {
        canonform_array *MV = NULL, *MF = NULL, *TV = NULL, *TF = NULL;
        int read = canonform_read_mesh(argv[2], &MV, &MF, NULL) == CANONFORM_OK &&
                   canonform_read_mesh(argv[3], &TV, &TF, NULL) == CANONFORM_OK;
        check(read, "the mesh and the tool's form are read");
        if (read) {
            double* Z = (double*)malloc(sizeof(double) * (size_t)(MV->shape[0] * 3));
            check(canonform_canonical_form((const double*)MV->data, MV->shape[0], (const int32_t*)MF->data,
                                           MF->shape[0], NULL, NULL, NULL, 0, 0, NULL, NULL, Z, NULL,
                                           NULL) == CANONFORM_OK &&
                      TV->shape[0] == MV->shape[0] &&
                      memcmp(Z, TV->data, sizeof(double) * (size_t)(MV->shape[0] * 3)) == 0,
                  "the C API's euclidean-N form is the tool's, byte for byte");
            free(Z);
        }
        canonform_array_free(MV);
        canonform_array_free(MF);
        canonform_array_free(TV);
        canonform_array_free(TF);
    }

    free(Y);
    free(Y2);
    free(bad);
    free(phi);
    free(dup);
    free(ply);
    free(missing);
    canonform_array_free(V);
    canonform_array_free(F);
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
