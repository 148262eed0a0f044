/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * canonform's C API: the library through plain C functions, for any language with a C foreign
 * function interface (the Python package calls it through ctypes) and any compiler (a DLL built
 * with MinGW-w64 works from a program built with MSVC: no C++ type crosses this boundary).
 *
 * Conventions (every function follows them):
 *
 *  - Status. Every function that can fail returns an int: CANONFORM_OK (0) or one of the
 *    CANONFORM_* error codes below. The library's message for the last failure on the calling
 *    thread is canonform_last_error() (UTF-8, a complete sentence naming the cause, as the tool
 *    prints it). No C++ exception ever leaves a function of this header.
 *  - Arrays in. Caller-owned, C order (row-major), contiguous: a mesh is `const double* V` of
 *    nv x 3 coordinates (x0 y0 z0 x1 ...) and `const int32_t* F` of nf x 3 vertex indices
 *    (0-based). They are read during the call only and never kept.
 *  - Arrays out. Either a caller-owned buffer of a size the caller knows (a canonical form:
 *    double[nv * 3], filled only on success), or a canonform_array the library allocates (sizes
 *    the caller cannot know in advance: a mesh read from a file, feature points), which the caller
 *    frees with canonform_array_free(). On failure no array is returned (the out pointer is set to
 *    NULL) and a caller-owned buffer may hold partial values.
 *  - Text out (JSON documents, summaries) is a NUL-terminated UTF-8 char* the library allocates;
 *    free it with canonform_free(). Invalid UTF-8 bytes of file contents are replaced by U+FFFD.
 *  - Paths are `const char*` in UTF-8 (on Linux: the file system's bytes, passed on as they are).
 *  - Progress. Long functions take a canonform_progress_fn and a user pointer (both may be NULL).
 *    The library calls it with a fraction in [0, 1] and a short stage label; returning 0 cancels:
 *    the function stops at the next check and returns CANONFORM_CANCELLED. It may be called from
 *    the calling thread and from the library's worker threads (never two at once for one call
 *    unless the function says so: canonform_retrieve's mesh stages run in parallel).
 *  - Threads. Functions may be called from several threads at once; `threads` arguments size the
 *    library's own parallel loops (0: every core). Results never depend on the thread count.
 *  - Integers that count things are int64_t; an out-of-range value is CANONFORM_INPUT_ERROR
 *    naming the argument and its range (the ranges of the canonform tool's options).
 *
 * Linking: find_package(canonform) gives the target canonform::c_api (libcanonform_c.so, or
 * canonform_c.dll with its import library); a C program includes <canonform/c_api/canonform.h>.
 * Functions of areas a build left out (views, retrieval: -DCANONFORM_VIEWS=OFF, ...) return
 * CANONFORM_UNSUPPORTED with a message saying so.
 */
#ifndef CANONFORM_C_API_CANONFORM_H
#define CANONFORM_C_API_CANONFORM_H

#include <stddef.h>
#include <stdint.h>

/* CANONFORM_C_EXPORT marks the API's functions: exported from the shared library (ELF default
 * visibility; dllexport while building the DLL, dllimport when using it). Define
 * CANONFORM_C_STATIC when linking a static build of this library. */
#if defined(CANONFORM_C_STATIC)
#define CANONFORM_C_EXPORT
#elif defined(_WIN32) || defined(__CYGWIN__)
#if defined(CANONFORM_C_BUILDING)
#define CANONFORM_C_EXPORT __declspec(dllexport)
#else
#define CANONFORM_C_EXPORT __declspec(dllimport)
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define CANONFORM_C_EXPORT __attribute__((visibility("default")))
#else
#define CANONFORM_C_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- version, errors, memory -------------------------------------------------------------- */

/* The C API's own version: raised whenever a function, struct or code of this header changes.
 * A caller compares canonform_api_version() with the value it was written for. */
#define CANONFORM_C_API_VERSION 1

/* Status codes. */
#define CANONFORM_OK 0
#define CANONFORM_INPUT_ERROR 1     /* the input cannot be processed (mesh, file, array, parameter) */
#define CANONFORM_NUMERICAL_ERROR 2 /* a numerical step failed (factorisation, non-finite values) */
#define CANONFORM_CANCELLED 3       /* a progress or log callback returned 0 */
#define CANONFORM_OUT_OF_MEMORY 4   /* an allocation failed */
#define CANONFORM_UNSUPPORTED 5     /* not part of this build (an area or backend left out) */
#define CANONFORM_INTERNAL_ERROR 6  /* anything else (a bug: the message says what failed) */

/* The library's version, "MAJOR.MINOR.PATCH" (the tool's --version). A static string. */
CANONFORM_C_EXPORT const char* canonform_version(void);

/* CANONFORM_C_API_VERSION of the library as built. */
CANONFORM_C_EXPORT int canonform_api_version(void);

/* The message of the last failed call on this thread (UTF-8), or "" if none failed yet. Valid
 * until the next call of this API on the same thread. */
CANONFORM_C_EXPORT const char* canonform_last_error(void);

/* The name of a status code ("CANONFORM_INPUT_ERROR"); "unknown" for others. A static string. */
CANONFORM_C_EXPORT const char* canonform_status_name(int status);

/* Frees text the library returned (char** outputs). NULL is allowed. */
CANONFORM_C_EXPORT void canonform_free(void* text);

/* Element types of a canonform_array. */
#define CANONFORM_FLOAT64 1
#define CANONFORM_FLOAT32 2
#define CANONFORM_INT32 3
#define CANONFORM_INT64 4

/* An array the library allocated: `ndim` (1 or 2) dimensions `shape`, elements of `type` in C
 * order at `data` (NULL when empty). Free it with canonform_array_free(). */
typedef struct canonform_array {
    int type;         /* CANONFORM_FLOAT64, FLOAT32, INT32 or INT64 */
    int ndim;         /* 1 or 2 */
    int64_t shape[2]; /* shape[1] is 1 when ndim is 1 */
    void* data;
} canonform_array;

/* Frees an array the library returned. NULL is allowed. */
CANONFORM_C_EXPORT void canonform_array_free(canonform_array* array);

/* Progress: `fraction` in [0, 1], `stage` a short UTF-8 label ("SMACOF", "conformal factor", ...),
 * valid during the call. Return non-zero to go on, 0 to cancel. */
typedef int (*canonform_progress_fn)(void* user, double fraction, const char* stage);

/* ---- meshes -------------------------------------------------------------------------------- */

/* Reads a mesh file: OFF, PLY (ASCII or binary), OBJ or STL, by extension. *V: FLOAT64 (nv, 3);
 * *F: INT32 (nf, 3) ((0, 3) for a point cloud); *quality (may be NULL if not wanted): FLOAT64
 * (nv,) the PLY's vertex quality, or (0,) when the file has none. INPUT_ERROR names the file and
 * the cause (missing, a folder, empty, unsupported format, a face index out of range, a header
 * that claims more than the file holds, malformed data). */
CANONFORM_C_EXPORT int canonform_read_mesh(const char* path, canonform_array** V, canonform_array** F,
                                           canonform_array** quality);

/* Writes a mesh in the format its file name names: .ply (binary, with quality), .off, .obj, .stl;
 * no extension: PLY. Atomic: a failure leaves no file. nf may be 0 (a point cloud; not STL);
 * quality (nv values, PLY only) may be NULL. */
CANONFORM_C_EXPORT int canonform_write_mesh(const char* path, const double* V, int64_t nv, const int32_t* F,
                                            int64_t nf, const double* quality);

/* The tool's --repair: merges duplicate vertices, removes zero-area and duplicate faces, keeps the
 * largest component, drops unreferenced vertices. *V_out FLOAT64 (n, 3), *F_out INT32 (m, 3),
 * *summary (may be NULL) a line saying what changed (free with canonform_free). */
CANONFORM_C_EXPORT int canonform_repair_mesh(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                                             canonform_array** V_out, canonform_array** F_out,
                                             char** summary);

/* Quadric edge collapse to about `vertices` vertices (MeshLab's filter with its defaults; the
 * tool's `simplify`). Needs the retrieval area (UNSUPPORTED otherwise). */
CANONFORM_C_EXPORT int canonform_simplify(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                                          int64_t vertices, canonform_array** V_out, canonform_array** F_out);

/* A procedural articulated figure, as `canonform generate OUT --vertices N --pose P --class BODY`
 * writes it (coordinates rounded to float32, given as FLOAT64). vertices in [500, 2000000]; pose 0-5
 * named poses, larger seeded random ones; body: standard, long-arms, short-legs, long-tail, stocky,
 * long-neck (NULL: standard). */
CANONFORM_C_EXPORT int canonform_figure(int64_t vertices, int64_t pose, const char* body,
                                        canonform_array** V_out, canonform_array** F_out);

/* ---- canonical forms ----------------------------------------------------------------------- */

/* The registry of canonical-form methods as a JSON array, in the order the tool lists them:
 * [{"name", "family" ("euclidean", "geodesic" or "none"), "help", "parameters": [{"name",
 * "default" (text), "help", "min", "max", "integer", "choices", "zero_means_default"}]}]. */
CANONFORM_C_EXPORT int canonform_methods_json(char** json);

/* The canonical form of a mesh by any method of the registry ("euclidean-N", "euclidean-A",
 * "geodesic-ls", "geodesic-classical", "geodesic-fast", "none"; NULL: "euclidean-N"), with
 * `nparams` parameters given by name and value as text (keys[i] = values[i], e.g. "beta" = "65",
 * as the tool's options), each checked by the registry: an unknown name or a value out of range is
 * INPUT_ERROR naming it. threads: the method's parallel loops (0: every core, at most 1024).
 * Y (caller-owned, nv x 3 doubles): the form, same vertex order and faces, in input units; the
 * same doubles `canonform canonical` writes for the same mesh and parameters. *quality (may be
 * NULL if not wanted): FLOAT64 (nv,), the per-vertex quality the tool writes with the form (the
 * conformal factor, for the methods that compute one), or (0,). *info (may be NULL): the JSON
 * object of `canonform canonical --json` without the tool's read, write and total seconds:
 * vertices, faces, then the method's summary (iterations, stresses, seconds...) in its order. A
 * form with a non-finite coordinate is NUMERICAL_ERROR. */
CANONFORM_C_EXPORT int canonform_canonical_form(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                                                const char* method, const char* const* keys,
                                                const char* const* values, int64_t nparams, int threads,
                                                canonform_progress_fn progress, void* user, double* Y,
                                                canonform_array** quality, char** info);

/* The discrete conformal factor (Pickup et al. 2015, eqs. 7-9). phi (caller-owned, nv doubles):
 * in [0, 1] if `normalize` (as `canonform conformal` stores it), else raw with area-weighted mean
 * zero. */
CANONFORM_C_EXPORT int canonform_conformal_factor(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                                                  int normalize, canonform_progress_fn progress, void* user,
                                                  double* phi);

/* Feature points: vertices that are strict maxima of the conformal factor over their ring-ring
 * (ring in [1, 10]), largest first, up to ceil(sqrt(nv)) (`canonform features`). fill: "none" or
 * "random" (tops them up with seeded random vertices: variant A; NULL: "none"); seed in
 * [0, 2^32). *indices: INT64 (k,) vertex indices. The progress function is only asked whether to
 * go on (its stages are those of the conformal factor). */
CANONFORM_C_EXPORT int canonform_feature_points(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                                                int64_t ring, const char* fill, int64_t seed,
                                                canonform_progress_fn progress, void* user,
                                                canonform_array** indices);

/* For benchmarks: runs method `method` at its defaults on one thread with no progress function,
 * validating the mesh first, and stores the seconds the library's call took (steady clock) in
 * *seconds: the bare C++ call next to which a binding's overhead is measured. */
CANONFORM_C_EXPORT int canonform_time_canonical_form(const double* V, int64_t nv, const int32_t* F,
                                                     int64_t nf, const char* method, double* seconds);

/* ---- the view descriptor (CM-BOF) ----------------------------------------------------------- */

/* The SIFT extractors' names, comma-separated ("canonform,opencv"): what `sift` arguments take.
 * A static string. */
CANONFORM_C_EXPORT const char* canonform_sift_backends(void);

/* 1 if this build has the SIFT extractor `name` (the `opencv` one is left out of builds without
 * OpenCV, such as the Python wheel), 0 if not or unknown. */
CANONFORM_C_EXPORT int canonform_sift_backend_available(const char* name);

/* The extractor used when a `sift` argument is NULL (the library's default). A static string. */
CANONFORM_C_EXPORT const char* canonform_default_sift(void);

/* The codebook-training methods this build has, comma-separated ("kmeans,lloyd,random"; builds
 * without FAISS lack "kmeans"). A static string. */
CANONFORM_C_EXPORT const char* canonform_codebook_methods(void);

/* The view descriptor of a mesh (`canonform descriptor`): pose normalisation (seed: its
 * rectilinearity restarts, [0, 2^32)), 66 depth views of image_size pixels ([32, 2048]), SIFT per
 * view (sift: NULL for the default, or a name of canonform_sift_backends()). Several components
 * are allowed.
 * Without a codebook (codebook_words NULL and codebook_path NULL): *features FLOAT32 (n, 128), the
 * SIFT descriptors of the 66 views stacked in view order, and *counts INT64 (66,) the keypoints of
 * each view. With a codebook, given as its words (codebook_words: nwords x 128 floats) or as a
 * codebook file (codebook_path): *features FLOAT32 (66, nwords), one bag-of-features histogram
 * (word counts) per view, and *counts INT64 (66,) the keypoints per view. */
CANONFORM_C_EXPORT int canonform_view_descriptor(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                                                 const float* codebook_words, int64_t nwords,
                                                 const char* codebook_path, const char* sift,
                                                 int64_t image_size, int64_t seed, canonform_array** features,
                                                 canonform_array** counts);

/* Trains a codebook of `words` visual words ([1, 1000000]) on n stacked SIFT descriptors
 * (descriptors: n x 128 floats; `canonform codebook`). sample: descriptors drawn (seeded) to train
 * on, 0 = all ([0, 2000000000]); seed [0, 2^32); method: "kmeans" (FAISS; NULL), "lloyd" or
 * "random". *words_out FLOAT32 (words, 128). Fewer descriptors than words is INPUT_ERROR. */
CANONFORM_C_EXPORT int canonform_train_codebook(const float* descriptors, int64_t n, int64_t words,
                                                int64_t sample, int64_t seed, const char* method,
                                                canonform_array** words_out);

/* Writes nwords x 128 words as a codebook file (the tool's format; atomic). */
CANONFORM_C_EXPORT int canonform_save_codebook(const char* path, const float* words, int64_t nwords);

/* Reads a codebook file: *words FLOAT32 (nwords, 128). */
CANONFORM_C_EXPORT int canonform_load_codebook(const char* path, canonform_array** words);

/* Reads a descriptor file (.cfvd, `canonform descriptor`). *meta (JSON): {"source", "views",
 * "image_size", "codebook_words", "keypoints_per_view"}; *data: FLOAT32 (views, codebook_words)
 * histograms when codebook_words > 0, else FLOAT32 (n, 128) the raw features stacked in view order
 * (keypoints_per_view splits them). */
CANONFORM_C_EXPORT int canonform_read_descriptor(const char* path, char** meta, canonform_array** data);

/* The clock-matching distance of two descriptors given as dense histograms (rows: views, columns:
 * words; counts >= 0, finite): the minimum over the 24 rotations of the cube of the summed view
 * distances. A and B must have the same number of views. */
CANONFORM_C_EXPORT int canonform_clock_distance(const double* A, int64_t views_a, int64_t words_a,
                                                const double* B, int64_t views_b, int64_t words_b,
                                                double* distance);

/* The n x n clock-matching distance matrix (`canonform distance`) of n descriptors, model k given
 * as dense histograms histograms[k] of views[k] x words[k] doubles (every words[k] equal: one
 * codebook). D (caller-owned, n x n floats): symmetric, zero diagonal. threads: 0 = every core. */
CANONFORM_C_EXPORT int canonform_distance_matrix(const double* const* histograms, const int64_t* views,
                                                 const int64_t* words, int64_t n, int threads,
                                                 canonform_progress_fn progress, void* user, float* D);

/* ---- retrieval ---------------------------------------------------------------------------------- */

/* The retrieval measures of an n x n distance matrix (`canonform evaluate --json`; psbTable's
 * definitions, normalised by C-1). The matrix is given either as D (rows x cols doubles) or as a
 * distance-matrix file D_path (float32 binary or .csv) (the other NULL); the classes either as
 * nlabels UTF-8 names or as a labels file labels_path (path,class rows). *json: {"micro",
 * "macro" ({nn, first_tier, second_tier, e_measure, dcg, queries}), "classes" ({class: measures}),
 * "precision", "recall" (20 points), "skipped_classes" (two models or fewer), then the five micro
 * measures and queries again at the top}. */
CANONFORM_C_EXPORT int canonform_evaluate(const double* D, int64_t rows, int64_t cols, const char* D_path,
                                          const char* const* labels, int64_t nlabels, const char* labels_path,
                                          char** json);

/* Reads a distance-matrix file (float32 binary, or .csv): *D FLOAT32 (n, n). */
CANONFORM_C_EXPORT int canonform_read_distance_matrix(const char* path, canonform_array** D);

/* Reads a labels file: *json a JSON array of [path, class] pairs in file order. */
CANONFORM_C_EXPORT int canonform_read_labels(const char* path, char** json);

/* A log line of canonform_retrieve (UTF-8, valid during the call). Return non-zero to go on, 0 to
 * stop the run (it then returns CANONFORM_CANCELLED). Called on the calling thread. */
typedef int (*canonform_log_fn)(void* user, const char* line);

/* The options of canonform_retrieve: `canonform retrieve`'s options of the same names. Fill it with
 * canonform_retrieve_options_init() (the tool's defaults), then set what differs. */
typedef struct canonform_retrieve_options {
    const char* dataset; /* the collection folder (required) */
    const char* out;     /* the run folder (required): written as the tool writes it, its cache reused */
    const char* labels;  /* the labels file; NULL: DATASET/labels.csv */
    const char*
        methods;   /* comma-separated method specs ("none,euclidean-N:beta=65,fused:none+euclidean-N") */
    int64_t words; /* codebook size [1, 1000000]; default 1500 */
    const char* codebook;    /* "kmeans" (default), "lloyd", "random", or a codebook file for every method */
    int64_t codebook_sample; /* descriptors drawn to train on, 0 = all */
    int64_t simplify;        /* simplify each mesh to about this many vertices first; 0 = no */
    double noise;            /* vertex noise, in [0, 10] */
    int64_t seed;            /* [0, 2^32) */
    const char* sift;        /* NULL: the default extractor */
    int repair;              /* non-zero: the tool's --repair */
    int threads;             /* 0 = every core */
} canonform_retrieve_options;

/* Sets every field to the tool's default (dataset, out, labels NULL; methods "none,euclidean-N"). */
CANONFORM_C_EXPORT void canonform_retrieve_options_init(canonform_retrieve_options* options);

/* A retrieval experiment over a labelled collection, as `canonform retrieve` runs it: per method,
 * canonical forms, 66 views and SIFT per mesh (in parallel, cached in OUT/cache), a codebook,
 * histograms, clock-matching distances and the measures; writes OUT as the tool does
 * (METHOD/distances.bin, metrics.json, pr.csv, report.md, ...; no pictures). Options are checked
 * before any work. progress: the fraction of each method's stages, its stage label prefixed with
 * "METHOD: " (called from worker threads too, one at a time); log: the tool's log lines. A
 * cancelled run stops between meshes; a second run continues from the cache.
 * *result (JSON): {"out", "report" (report.md's markdown), "methods": {NAME: {"folder", "meshes",
 * "failed", "cached", "measures" (as canonform_evaluate, or null), "no_measures",
 * "pose_consistency" (null if not measured), "pose_consistency_pairs", "forms_seconds",
 * "codebook_seconds", "distances_seconds"}}}. */
CANONFORM_C_EXPORT int canonform_retrieve(const canonform_retrieve_options* options,
                                          canonform_progress_fn progress, void* progress_user,
                                          canonform_log_fn log, void* log_user, char** result);

#ifdef __cplusplus
}
#endif

#endif /* CANONFORM_C_API_CANONFORM_H */
