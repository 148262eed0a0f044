// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/c_api/c_api_support.h"

#include "canonform/common/version.h"

#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>

namespace canonform::c_api {

namespace {

std::string& last_error() {
    thread_local std::string message;
    return message;
}

}  // namespace

const char* last_error_text() noexcept {
    return last_error().c_str();
}

int fail(int status, const std::string& message) {
    try {
        last_error() = message;
    } catch (...) {
        // no memory even for the message: keep the status
    }
    return status;
}

int status_of_current_exception() noexcept {
    try {
        throw;
    } catch (const Cancelled& e) {
        return fail(CANONFORM_CANCELLED, e.what());
    } catch (const InputError& e) {
        return fail(CANONFORM_INPUT_ERROR, e.what());
    } catch (const NumericalError& e) {
        return fail(CANONFORM_NUMERICAL_ERROR, e.what());
    } catch (const Unsupported& e) {
        return fail(CANONFORM_UNSUPPORTED, e.what());
    } catch (const std::bad_alloc&) {
        return fail(CANONFORM_OUT_OF_MEMORY, "out of memory");
    } catch (const std::invalid_argument& e) {
        return fail(CANONFORM_INPUT_ERROR, e.what());
    } catch (const std::exception& e) {
        return fail(CANONFORM_INTERNAL_ERROR, e.what());
    } catch (...) {
        return fail(CANONFORM_INTERNAL_ERROR, "an unknown exception inside the library");
    }
}

void check_range(const char* name, std::int64_t value, std::int64_t lo, std::int64_t hi) {
    if (value < lo || value > hi)
        throw InputError(std::string(name) + " must be between " + std::to_string(lo) + " and " +
                         std::to_string(hi) + ", got " + std::to_string(value));
}

std::string text_in(const char* s, const char* name) {
    if (!s) throw InputError(std::string(name) + " is NULL: a text is needed");
    return s;
}

namespace {

void check_rows(const void* p, std::int64_t rows, const char* name, const char* what) {
    if (rows < 0)
        throw InputError(std::string(name) + ": a negative " + what + " count (" + std::to_string(rows) +
                         ")");
    if (rows > 0 && !p)
        throw InputError(std::string(name) + " is NULL with " + std::to_string(rows) + " " + what);
}

}  // namespace

Eigen::MatrixXd vertices_in(const double* V, std::int64_t nv, const char* name) {
    check_rows(V, nv, name, "rows");
    if (nv > std::numeric_limits<int>::max())
        throw InputError(std::string(name) + " has " + std::to_string(nv) +
                         " vertices, more than 32-bit face indices address");
    if (nv == 0) return Eigen::MatrixXd(0, 3);
    return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(V, nv, 3);
}

Eigen::MatrixXi faces_in(const std::int32_t* F, std::int64_t nf, const char* name) {
    check_rows(F, nf, name, "rows");
    if (nf == 0) return Eigen::MatrixXi(0, 3);
    return Eigen::Map<const Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>>(F, nf, 3)
        .cast<int>();
}

Eigen::MatrixXd matrix_in(const double* A, std::int64_t rows, std::int64_t cols, const char* name) {
    check_rows(A, rows, name, "rows");
    if (cols < 0)
        throw InputError(std::string(name) + ": a negative column count (" + std::to_string(cols) + ")");
    if (rows == 0 || cols == 0) return Eigen::MatrixXd(rows, cols);
    return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(A, rows,
                                                                                                    cols);
}

canonform_array* new_array(int type, int ndim, std::int64_t rows, std::int64_t cols) {
    std::size_t item = 0;
    switch (type) {
        case CANONFORM_FLOAT64:
        case CANONFORM_INT64:
            item = 8;
            break;
        case CANONFORM_FLOAT32:
        case CANONFORM_INT32:
            item = 4;
            break;
        default:
            throw std::logic_error("new_array: unknown type");
    }
    if (ndim == 1) cols = 1;
    auto* a = static_cast<canonform_array*>(std::malloc(sizeof(canonform_array)));
    if (!a) throw std::bad_alloc();
    a->type = type;
    a->ndim = ndim;
    a->shape[0] = rows;
    a->shape[1] = cols;
    a->data = nullptr;
    const std::size_t bytes = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols) * item;
    if (bytes > 0) {
        a->data = std::malloc(bytes);
        if (!a->data) {
            std::free(a);
            throw std::bad_alloc();
        }
    }
    return a;
}

ArrayPtr array_out(const Eigen::MatrixXd& M) {
    ArrayPtr a(new_array(CANONFORM_FLOAT64, 2, M.rows(), M.cols()));
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        a.data<double>(), M.rows(), M.cols()) = M;
    return ArrayPtr(a.release());
}

ArrayPtr array_out(const Eigen::MatrixXi& M) {
    ArrayPtr a(new_array(CANONFORM_INT32, 2, M.rows(), M.cols()));
    Eigen::Map<Eigen::Matrix<std::int32_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        a.data<std::int32_t>(), M.rows(), M.cols()) = M.cast<std::int32_t>();
    return ArrayPtr(a.release());
}

ArrayPtr vector_out(const Eigen::VectorXd& v) {
    ArrayPtr a(new_array(CANONFORM_FLOAT64, 1, v.size()));
    if (v.size()) std::memcpy(a.p->data, v.data(), sizeof(double) * static_cast<std::size_t>(v.size()));
    return ArrayPtr(a.release());
}

ArrayPtr indices_out(const std::vector<int>& v) {
    ArrayPtr a(new_array(CANONFORM_INT64, 1, static_cast<std::int64_t>(v.size())));
    for (std::size_t k = 0; k < v.size(); ++k) a.data<std::int64_t>()[k] = v[k];
    return ArrayPtr(a.release());
}

char* text_out(const std::string& s) {
    auto* p = static_cast<char*>(std::malloc(s.size() + 1));
    if (!p) throw std::bad_alloc();
    std::memcpy(p, s.c_str(), s.size() + 1);
    return p;
}

ProgressFn progress_in(canonform_progress_fn fn, void* user) {
    if (!fn) return {};
    auto lock = std::make_shared<std::mutex>();
    return [fn, user, lock](double fraction, const char* stage) {
        std::lock_guard<std::mutex> hold(*lock);
        return fn(user, fraction, stage ? stage : "") != 0;
    };
}

}  // namespace canonform::c_api

// ---- the general functions of canonform.h -----------------------------------------------------
using namespace canonform::c_api;

extern "C" {

const char* canonform_version(void) {
    return canonform::version();
}

int canonform_api_version(void) {
    return CANONFORM_C_API_VERSION;
}

const char* canonform_last_error(void) {
    return last_error_text();
}

const char* canonform_status_name(int status) {
    switch (status) {
        case CANONFORM_OK:
            return "CANONFORM_OK";
        case CANONFORM_INPUT_ERROR:
            return "CANONFORM_INPUT_ERROR";
        case CANONFORM_NUMERICAL_ERROR:
            return "CANONFORM_NUMERICAL_ERROR";
        case CANONFORM_CANCELLED:
            return "CANONFORM_CANCELLED";
        case CANONFORM_OUT_OF_MEMORY:
            return "CANONFORM_OUT_OF_MEMORY";
        case CANONFORM_UNSUPPORTED:
            return "CANONFORM_UNSUPPORTED";
        case CANONFORM_INTERNAL_ERROR:
            return "CANONFORM_INTERNAL_ERROR";
        default:
            return "unknown";
    }
}

void canonform_free(void* text) {
    std::free(text);
}

void canonform_array_free(canonform_array* array) {
    if (!array) return;
    std::free(array->data);
    std::free(array);
}

}  // extern "C"
