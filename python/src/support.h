// SPDX-License-Identifier: GPL-3.0-or-later
// canonform Python module: what every binding shares - numpy arrays in and out, the library's
// errors as Python exceptions, and calls that release the GIL and stop on Ctrl-C.
//
// Arrays in: V any float32/float64 array of shape (#V, 3), F any integer array of shape (#F, 3),
// any memory order or strides. Each is copied once, into the matrix type the library's functions
// take (Eigen::MatrixXd / MatrixXi, column-major): the only copy, converting the type on the way.
// Arrays out: new C-ordered numpy arrays that own their memory (flags.owndata), filled from the
// library's result.
//
// Errors: canonform::InputError -> canonform.InputError (a ValueError), NumericalError ->
// canonform.NumericalError (a RuntimeError), Cancelled -> canonform.Cancelled (a RuntimeError),
// with the library's message (invalid UTF-8 bytes, e.g. of a file name, replaced by U+FFFD).
//
// Calls: Call::run(f) runs f with the GIL released. The library reports progress through a
// ProgressFn (common/errors.h) and stops with Cancelled when it returns false; Call::progress() is
// such a function: it takes the GIL, runs Python's signal handlers (Ctrl-C raises
// KeyboardInterrupt there) and calls the user's callable, and returns false when either raised or
// the callable returned False. run() then re-raises the KeyboardInterrupt (or the callable's
// exception) in place of Cancelled.
#pragma once

#include "canonform/common/errors.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>

#include <exception>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace canonform::python {

namespace py = pybind11;

/// A Python str from UTF-8 bytes; invalid bytes become U+FFFD (never a UnicodeDecodeError).
py::str text(const std::string& s);

/// Registers canonform.InputError, NumericalError and Cancelled and the translation of the
/// library's exceptions (once, from the module's init).
void register_errors(py::module_& m);

/// V: an array of shape (n, 3), float32 or float64 (InputError naming `name`, the shape or the
/// dtype otherwise).
Eigen::MatrixXd vertices_in(const py::handle& V, const char* name = "V");
/// F: an array of shape (m, 3) of any integer type whose values fit in 32 bits (range against #V
/// is checked by the library); None gives (0, 3) when `allow_none`.
Eigen::MatrixXi faces_in(const py::handle& F, const char* name = "F", bool allow_none = false);
/// A float array of shape (n, cols) (cols < 0: any) as float64.
Eigen::MatrixXd matrix_in(const py::handle& a, const char* name, Eigen::Index cols = -1);
/// A float vector of length n (any float or integer dtype) as float64.
Eigen::VectorXd vector_in(const py::handle& a, const char* name);
/// Descriptors: an array of shape (n, 128), float32 or float64, as float32 rows.
Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor> descriptors_in(const py::handle& a, const char* name);

/// New C-ordered arrays owning their memory.
py::array_t<double> array_out(const Eigen::MatrixXd& M);
py::array_t<float> array_out(const Eigen::MatrixXf& M);
py::array_t<std::int32_t> array_out(const Eigen::MatrixXi& M);
py::array_t<float> array_out(const Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor>& M);
py::array_t<double> array_out(const Eigen::VectorXd& v);
py::array_t<std::int64_t> indices_out(const std::vector<int>& v);

/// A path argument (str, bytes or os.PathLike) as the file system's bytes.
std::string path_in(const py::handle& p);

/// A library call from Python: GIL released, Ctrl-C and an optional progress callable honoured.
class Call {
public:
    /// `callback`: None, or callable(fraction: float, stage: str) -> bool | None (False cancels).
    explicit Call(py::object callback = py::none());

    /// The ProgressFn to hand to the library (valid while this Call lives).
    ProgressFn progress() const;

    /// A ProgressFn that only watches for Ctrl-C (for stages whose progress the user did not ask for).
    ProgressFn interrupt_only() const;

    /// Throws Cancelled (remembering why) if Ctrl-C was pressed or `progress` says stop: for
    /// loops in the bindings themselves. Call with the GIL released.
    void check(double fraction, const char* stage) const { report_progress(progress(), fraction, stage); }

    /// f() with the GIL released; Cancelled becomes the Python exception that caused it
    /// (KeyboardInterrupt for Ctrl-C, the callable's own exception) or canonform.Cancelled.
    template <class F>
    auto run(F&& f) const -> decltype(f()) {
        try {
            py::gil_scoped_release release;
            return f();
        } catch (const Cancelled&) {
            rethrow_cause();
            throw;
        }
    }

    /// Re-raises what made the library stop, if it was a Python exception (GIL held).
    void rethrow_cause() const;

private:
    struct State {
        py::object callback;
        std::exception_ptr cause;  // the Python exception that stopped the call
    };
    std::shared_ptr<State> state_;
};

}  // namespace canonform::python
