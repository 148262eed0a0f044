// SPDX-License-Identifier: GPL-3.0-or-later
#include "support.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <sstream>
#include <stdexcept>

namespace canonform::python {

py::str text(const std::string& s) {
    PyObject* o = PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "replace");
    if (!o) throw py::error_already_set();
    return py::reinterpret_steal<py::str>(o);
}

namespace {

PyObject* g_input_error = nullptr;
PyObject* g_numerical_error = nullptr;
PyObject* g_cancelled = nullptr;

void set_error(PyObject* type, const char* what) {
    PyObject* msg = PyUnicode_DecodeUTF8(what, static_cast<Py_ssize_t>(std::strlen(what)), "replace");
    if (!msg) return;  // the decoding error stands
    PyErr_SetObject(type, msg);
    Py_DECREF(msg);
}

std::string shape_of(const py::array& a) {
    std::ostringstream s;
    s << "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s << (k ? ", " : "") << a.shape(k);
    s << (a.ndim() == 1 ? ",)" : ")");
    return s.str();
}

std::string dtype_of(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

/// The object as an array without copying (np.asarray); InputError if it cannot be one.
py::array as_array(const py::handle& obj, const char* name) {
    if (obj.is_none()) throw InputError(std::string(name) + " is None: an array is needed");
    py::array a = py::array::ensure(obj);
    if (!a) {
        PyErr_Clear();
        throw InputError(std::string(name) + " cannot be read as a numpy array");
    }
    if (a.dtype().kind() == 'O') throw InputError(std::string(name) + " is an array of Python objects: numbers are needed");
    return a;
}

void check_2d(const py::array& a, const char* name, Eigen::Index cols) {
    if (a.ndim() != 2 || (cols >= 0 && a.shape(1) != cols)) {
        std::ostringstream m;
        m << name << " must have shape (n, " << (cols >= 0 ? std::to_string(cols) : std::string("k")) << "), got shape "
          << shape_of(a);
        throw InputError(m.str());
    }
}

/// Element (i, j) of a 2-D array of type T with any strides (memcpy: numpy allows unaligned data).
template <class T>
T at(const char* base, py::ssize_t s0, py::ssize_t s1, py::ssize_t i, py::ssize_t j) {
    T v;
    std::memcpy(&v, base + i * s0 + j * s1, sizeof(T));
    return v;
}

template <class T, class M>
void fill_float(const py::array& a, M& out) {
    const char* base = static_cast<const char*>(a.data());
    const py::ssize_t s0 = a.strides(0), s1 = a.ndim() > 1 ? a.strides(1) : 0;
    for (py::ssize_t i = 0; i < a.shape(0); ++i)
        for (Eigen::Index j = 0; j < out.cols(); ++j)
            out(i, j) = static_cast<typename M::Scalar>(at<T>(base, s0, s1, i, j));
}

template <class M>
void fill_any_float(const py::array& a, M& out, const char* name, bool integers_too) {
    const py::dtype dt = a.dtype();
    const char kind = dt.kind();
    const auto size = dt.itemsize();
    if (kind == 'f' && size == 8) return fill_float<double>(a, out);
    if (kind == 'f' && size == 4) return fill_float<float>(a, out);
    if (integers_too && (kind == 'i' || kind == 'u')) {
        py::array f = py::array_t<double, py::array::forcecast>::ensure(a);
        if (!f) throw py::error_already_set();
        return fill_float<double>(f, out);
    }
    throw InputError(std::string(name) + " must be float32 or float64, got dtype " + dtype_of(a));
}

}  // namespace

void register_errors(py::module_& m) {
    g_input_error = PyErr_NewExceptionWithDoc(
        "canonform.InputError",
        "The input cannot be processed (a bad mesh, file, array or parameter); the message names the cause. "
        "A ValueError.",
        PyExc_ValueError, nullptr);
    g_numerical_error = PyErr_NewExceptionWithDoc(
        "canonform.NumericalError",
        "A numerical step failed (factorisation, non-finite values, residual above tolerance). A RuntimeError.",
        PyExc_RuntimeError, nullptr);
    g_cancelled = PyErr_NewExceptionWithDoc(
        "canonform.Cancelled", "The progress callable returned False. A RuntimeError.", PyExc_RuntimeError, nullptr);
    if (!g_input_error || !g_numerical_error || !g_cancelled) throw py::error_already_set();
    m.attr("InputError") = py::handle(g_input_error);
    m.attr("NumericalError") = py::handle(g_numerical_error);
    m.attr("Cancelled") = py::handle(g_cancelled);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const py::error_already_set&) {
            throw;  // pybind11's own
        } catch (const py::builtin_exception&) {
            throw;
        } catch (const InputError& e) {
            set_error(g_input_error, e.what());
        } catch (const NumericalError& e) {
            set_error(g_numerical_error, e.what());
        } catch (const Cancelled& e) {
            set_error(g_cancelled, e.what());
        } catch (const std::bad_alloc&) {
            PyErr_SetString(PyExc_MemoryError, "out of memory");
        } catch (const std::invalid_argument& e) {
            set_error(PyExc_ValueError, e.what());
        } catch (const std::exception& e) {
            set_error(PyExc_RuntimeError, e.what());
        }
    });
}

Eigen::MatrixXd vertices_in(const py::handle& V, const char* name) {
    const py::array a = as_array(V, name);
    check_2d(a, name, 3);
    Eigen::MatrixXd out(a.shape(0), 3);
    fill_any_float(a, out, name, false);
    return out;
}

Eigen::MatrixXi faces_in(const py::handle& F, const char* name, bool allow_none) {
    if (allow_none && F.is_none()) return Eigen::MatrixXi(0, 3);
    const py::array a = as_array(F, name);
    check_2d(a, name, 3);
    const py::dtype dt = a.dtype();
    const char kind = dt.kind();
    if (kind != 'i' && kind != 'u')
        throw InputError(std::string(name) + " must be an integer array (face indices), got dtype " + dtype_of(a));
    // Every integer type as 64 bits (uint64 beyond int64 stays visibly out of range), then range-checked.
    Eigen::MatrixXi out(a.shape(0), 3);
    const char* base = static_cast<const char*>(a.data());
    const py::ssize_t s0 = a.strides(0), s1 = a.strides(1);
    const auto size = dt.itemsize();
    for (py::ssize_t i = 0; i < a.shape(0); ++i)
        for (int j = 0; j < 3; ++j) {
            long double v = 0;
            if (kind == 'i') {
                if (size == 1) v = at<std::int8_t>(base, s0, s1, i, j);
                else if (size == 2) v = at<std::int16_t>(base, s0, s1, i, j);
                else if (size == 4) v = at<std::int32_t>(base, s0, s1, i, j);
                else v = static_cast<long double>(at<std::int64_t>(base, s0, s1, i, j));
            } else {
                if (size == 1) v = at<std::uint8_t>(base, s0, s1, i, j);
                else if (size == 2) v = at<std::uint16_t>(base, s0, s1, i, j);
                else if (size == 4) v = at<std::uint32_t>(base, s0, s1, i, j);
                else v = static_cast<long double>(at<std::uint64_t>(base, s0, s1, i, j));
            }
            if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) {
                std::ostringstream m;
                m.precision(20);
                m << "face index " << v << " (" << name << "[" << i << ", " << j << "]) is out of range";
                throw InputError(m.str());
            }
            out(i, j) = static_cast<int>(v);
        }
    return out;
}

Eigen::MatrixXd matrix_in(const py::handle& obj, const char* name, Eigen::Index cols) {
    const py::array a = as_array(obj, name);
    check_2d(a, name, cols);
    Eigen::MatrixXd out(a.shape(0), a.shape(1));
    fill_any_float(a, out, name, true);
    return out;
}

Eigen::VectorXd vector_in(const py::handle& obj, const char* name) {
    const py::array a = as_array(obj, name);
    if (a.ndim() != 1) throw InputError(std::string(name) + " must be one-dimensional, got shape " + shape_of(a));
    Eigen::MatrixXd out(a.shape(0), 1);
    fill_any_float(a, out, name, true);
    return out.col(0);
}

Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor> descriptors_in(const py::handle& obj, const char* name) {
    const py::array a = as_array(obj, name);
    check_2d(a, name, 128);
    Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor> out(a.shape(0), 128);
    fill_any_float(a, out, name, false);
    return out;
}

namespace {

template <class T, class M>
py::array_t<T> out_2d(const M& m) {
    py::array_t<T> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
    auto r = a.template mutable_unchecked<2>();
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j) r(i, j) = static_cast<T>(m(i, j));
    return a;
}

}  // namespace

py::array_t<double> array_out(const Eigen::MatrixXd& M) { return out_2d<double>(M); }
py::array_t<float> array_out(const Eigen::MatrixXf& M) { return out_2d<float>(M); }
py::array_t<std::int32_t> array_out(const Eigen::MatrixXi& M) { return out_2d<std::int32_t>(M); }
py::array_t<float> array_out(const Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor>& M) {
    py::array_t<float> a({static_cast<py::ssize_t>(M.rows()), static_cast<py::ssize_t>(128)});
    if (M.size()) std::memcpy(a.mutable_data(), M.data(), sizeof(float) * static_cast<size_t>(M.size()));
    return a;
}

py::array_t<double> array_out(const Eigen::VectorXd& v) {
    py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
    if (v.size()) std::memcpy(a.mutable_data(), v.data(), sizeof(double) * static_cast<size_t>(v.size()));
    return a;
}

py::array_t<std::int64_t> indices_out(const std::vector<int>& v) {
    py::array_t<std::int64_t> a(static_cast<py::ssize_t>(v.size()));
    auto* d = a.mutable_data();
    for (size_t k = 0; k < v.size(); ++k) d[k] = v[k];
    return a;
}

std::string path_in(const py::handle& p) {
    if (p.is_none()) throw InputError("a path is needed, got None");
    // os.fsencode: str, bytes or os.PathLike -> bytes (surrogate escapes back to the original bytes)
    const py::object b = py::module_::import("os").attr("fsencode")(p);
    return b.cast<std::string>();
}

Call::Call(py::object callback) : state_(std::make_shared<State>()) {
    if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
        throw InputError("progress must be a callable(fraction, stage) or None");
    state_->callback = std::move(callback);
}

namespace {

/// One progress report: Python's signal handlers, then the callable (if any); false to stop, with
/// the Python exception that says why (if one did) in *cause.
bool poll(const py::object* callback, std::exception_ptr* cause, double fraction, const char* stage) {
    py::gil_scoped_acquire gil;
    try {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // KeyboardInterrupt, or a handler's exception
        if (callback && !callback->is_none()) {
            const py::object r = (*callback)(fraction, text(stage ? stage : ""));
            if (r.ptr() == Py_False) return false;  // canonform.Cancelled
        }
        return true;
    } catch (...) {
        *cause = std::current_exception();
        return false;
    }
}

}  // namespace

ProgressFn Call::progress() const {
    const std::shared_ptr<State> s = state_;
    return [s](double fraction, const char* stage) { return poll(&s->callback, &s->cause, fraction, stage); };
}

ProgressFn Call::interrupt_only() const {
    const std::shared_ptr<State> s = state_;
    return [s](double fraction, const char* stage) { return poll(nullptr, &s->cause, fraction, stage); };
}

void Call::rethrow_cause() const {
    if (state_->cause) {
        std::exception_ptr p = state_->cause;
        state_->cause = nullptr;
        std::rethrow_exception(p);
    }
}

}  // namespace canonform::python
