// SPDX-License-Identifier: GPL-3.0-or-later
// canonform C API (canonform.h): what every function of it shares - the guard that turns the
// library's exceptions into status codes and the thread's last message, the checks of array
// arguments, the arrays and texts the library hands out, and the progress adapter.
#pragma once

#include "canonform/c_api/canonform.h"
#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace canonform::c_api {

/// Thrown for a function or backend this build does not have (CANONFORM_UNSUPPORTED).
class Unsupported : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The calling thread's last message ("" if none).
const char* last_error_text() noexcept;
/// Records `message` as the calling thread's last error and returns `status`.
int fail(int status, const std::string& message);

/// Runs f(); returns CANONFORM_OK, or the status of the exception it threw (InputError,
/// NumericalError, Cancelled, Unsupported, std::bad_alloc, std::invalid_argument: input, anything
/// else: internal) with its message recorded. Nothing escapes.
template <class F>
int guarded(F&& f) noexcept;

/// Checks that an output pointer is given (InputError naming it otherwise).
template <class T>
void require_out(T* p, const char* name) {
    if (!p) throw InputError(std::string(name) + " is NULL: an output pointer is needed");
}

/// A count argument in [lo, hi] (InputError "NAME must be between LO and HI, got X").
void check_range(const char* name, std::int64_t value, std::int64_t lo, std::int64_t hi);
/// A text argument that must be given.
std::string text_in(const char* s, const char* name);

/// nv x 3 row-major coordinates as the library's matrix (InputError for a negative count, a NULL
/// pointer with rows, or more rows than 32-bit face indices can address).
Eigen::MatrixXd vertices_in(const double* V, std::int64_t nv, const char* name = "V");
/// nf x 3 row-major indices (range against #V is the library's check).
Eigen::MatrixXi faces_in(const std::int32_t* F, std::int64_t nf, const char* name = "F");
/// rows x cols row-major doubles.
Eigen::MatrixXd matrix_in(const double* A, std::int64_t rows, std::int64_t cols, const char* name);

/// A new library array (malloc'ed data) of the given type and shape; ndim 1 uses rows only.
canonform_array* new_array(int type, int ndim, std::int64_t rows, std::int64_t cols = 1);
/// Owns a library array until release() hands it to the caller.
struct ArrayPtr {
    canonform_array* p = nullptr;
    explicit ArrayPtr(canonform_array* a) : p(a) {}
    ArrayPtr(const ArrayPtr&) = delete;
    ArrayPtr& operator=(const ArrayPtr&) = delete;
    ArrayPtr(ArrayPtr&& o) noexcept : p(o.release()) {}
    ArrayPtr& operator=(ArrayPtr&& o) noexcept {
        if (this != &o) {
            canonform_array_free(p);
            p = o.release();
        }
        return *this;
    }
    ~ArrayPtr() { canonform_array_free(p); }
    canonform_array* release() { return std::exchange(p, nullptr); }
    template <class T>
    T* data() const {
        return static_cast<T*>(p->data);
    }
};
ArrayPtr array_out(const Eigen::MatrixXd& M);   // FLOAT64 (rows, cols)
ArrayPtr array_out(const Eigen::MatrixXi& M);   // INT32 (rows, cols)
ArrayPtr vector_out(const Eigen::VectorXd& v);  // FLOAT64 (n,)
/// INT64 (n,)
ArrayPtr indices_out(const std::vector<int>& v);

/// A malloc'ed NUL-terminated copy (canonform_free frees it).
char* text_out(const std::string& s);

/// The user's progress function as the library's ProgressFn (empty when fn is NULL): calls made
/// one at a time (a mutex), non-zero to go on.
ProgressFn progress_in(canonform_progress_fn fn, void* user);

/// Sets *out to NULL (when given) before any work: no stale pointer is left on failure.
template <class... T>
void clear_outputs(T**... outs) {
    ((outs ? (*outs = nullptr, 0) : 0), ...);
}

// ---- the guard ------------------------------------------------------------------------------
int status_of_current_exception() noexcept;

template <class F>
int guarded(F&& f) noexcept {
    try {
        f();
        return CANONFORM_OK;
    } catch (...) {
        return status_of_current_exception();
    }
}

}  // namespace canonform::c_api
