// The extension module microshadow._core: broadcasting helpers, exception translation and the registration
// of every part (docs/python.md).
#include <fmt/format.h>
#include <microshadow/io/error.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "py_common.h"

namespace msh::py {

namespace {

// dtype of one argument: 'd' float64 vote, 'f' float32 vote, 'w' weak (Python scalar, no vote).
char dtype_vote(pyb::handle obj, const pyb::array& arr, const char* name) {
  const char kind = arr.dtype().kind();
  if (kind == 'c' || !(kind == 'f' || kind == 'i' || kind == 'u' || kind == 'b'))
    throw pyb::value_error(fmt::format("{} must be a real number or an array of real numbers, got dtype {}",
                                       name, std::string(pyb::str(arr.dtype()))));
  if (PyFloat_Check(obj.ptr()) || PyLong_Check(obj.ptr()) || PyBool_Check(obj.ptr())) {
    // Python float/int/bool (including np.float64, a float subclass): no vote, like numpy's value-based
    // casting ... except np.float64, which numpy treats as float64 too; we follow the "weak scalar" rule.
    return 'w';
  }
  if (kind == 'f') return arr.dtype().itemsize() <= 4 ? 'f' : 'd';
  return 'd';
}

// The first element (lowest index) of argument a whose values are outside its domain, or SIZE_MAX.
template <class T>
std::size_t first_outside(const Broadcast& b, std::size_t a, Domain d) {
  const T* p = b.data<T>(a);
  const std::size_t k = std::size_t(std::max(1, b.core[a]));
  const std::size_t count = b.step[a] == 0 ? std::min<std::size_t>(b.n, 1) : b.n;
  for (std::size_t e = 0; e < count; ++e) {
    const T* q = p + e * k;
    bool ok = true, nonzero = false;
    for (std::size_t c = 0; c < k; ++c) {
      const double v = double(q[c]);
      ok &= d == Domain::Uniform ? (v >= 0 && v < 1) : std::isfinite(v);
      nonzero |= v != 0;
    }
    if (!ok || (d == Domain::Direction && !nonzero)) return e;
  }
  return std::numeric_limits<std::size_t>::max();
}

template <class T>
void check_domains(const Broadcast& b, const std::vector<ArgSpec>& args) {
  std::size_t bad = std::numeric_limits<std::size_t>::max(), which = 0;
  for (std::size_t a = 0; a < args.size(); ++a) {
    if (args[a].domain == Domain::Checked) continue;
    const std::size_t e = first_outside<T>(b, a, args[a].domain);
    if (e < bad) bad = e, which = a;
  }
  if (bad == std::numeric_limits<std::size_t>::max()) return;
  const ArgSpec& s = args[which];
  const std::size_t k = std::size_t(std::max(1, s.core));
  const T* q = b.data<T>(which) + (b.step[which] == 0 ? 0 : bad * k);
  std::string value;
  for (std::size_t c = 0; c < k; ++c) value += fmt::format("{}{}", c ? ", " : "", double(q[c]));
  if (k > 1) value = "(" + value + ")";
  const char* what = s.domain == Domain::Uniform     ? "in [0, 1)"
                     : s.domain == Domain::Direction ? "a finite, non-zero vector"
                                                     : "finite";
  throw InputError(fmt::format("{} must be {}, got {} (element {})", s.name, what, value, bad));
}

}  // namespace

Broadcast broadcast(const std::vector<ArgSpec>& args, bool force_f64) {
  Broadcast b;
  const pyb::module_ np = pyb::module_::import("numpy");
  std::vector<pyb::array> raw;
  bool any_f32 = false, any_f64 = force_f64;
  for (const ArgSpec& a : args) {
    pyb::array arr;
    try {
      arr = pyb::array::ensure(a.obj);
      if (!arr) arr = np.attr("asarray")(a.obj);
    } catch (const pyb::error_already_set&) {
      throw pyb::value_error(fmt::format("{} must be a real number or an array of real numbers", a.name));
    }
    const char vote = dtype_vote(a.obj, arr, a.name);
    any_f32 |= vote == 'f';
    any_f64 |= vote == 'd';
    if (a.core > 0 && (arr.ndim() < 1 || arr.shape(arr.ndim() - 1) != a.core))
      throw pyb::value_error(
          fmt::format("{} must have a last axis of length {} (one {}-vector per element), got shape {}",
                      a.name, a.core, a.core, std::string(pyb::str(pyb::tuple(np.attr("shape")(arr))))));
    raw.push_back(arr);
  }
  b.f32 = any_f32 && !any_f64;
  // Broadcast shape of the non-core dimensions (numpy's rule: align right, 1 stretches).
  std::size_t nd = 0;
  for (std::size_t i = 0; i < raw.size(); ++i)
    nd = std::max(nd, std::size_t(raw[i].ndim() - (args[i].core > 0 ? 1 : 0)));
  b.shape.assign(nd, 1);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const int cd = args[i].core > 0 ? 1 : 0;
    const std::size_t ndi = std::size_t(raw[i].ndim() - cd);
    if (ndi > 0 || cd) b.all_scalar = false;
    for (std::size_t k = 0; k < ndi; ++k) {
      const pyb::ssize_t s = raw[i].shape(pyb::ssize_t(k)), o = nd - ndi + k;
      if (s == b.shape[o] || s == 1) continue;
      if (b.shape[o] == 1) {
        b.shape[o] = s;
        continue;
      }
      std::string shapes;
      for (std::size_t j = 0; j < raw.size(); ++j)
        shapes += fmt::format("{}{} {}", shapes.empty() ? "" : ", ", args[j].name,
                              std::string(pyb::str(pyb::tuple(np.attr("shape")(raw[j])))));
      throw pyb::value_error(
          fmt::format("shape mismatch: the arguments cannot be broadcast together ({})", shapes));
    }
  }
  for (pyb::ssize_t s : b.shape) b.n *= std::size_t(s);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const int core = args[i].core;
    const int cd = core > 0 ? 1 : 0;
    pyb::array a = raw[i];
    const std::size_t elems = std::size_t(a.size()) / std::size_t(std::max(1, core));
    const bool full = std::size_t(a.ndim() - cd) == nd && [&] {
      for (std::size_t k = 0; k < nd; ++k)
        if (a.shape(pyb::ssize_t(k)) != b.shape[k]) return false;
      return true;
    }();
    if (elems == 1 && b.n != 1) {
      b.step.push_back(0);  // one value for every element
    } else if (full) {
      b.step.push_back(std::max(1, core));
    } else {
      std::vector<pyb::ssize_t> target = b.shape;
      if (core) target.push_back(core);
      a = np.attr("broadcast_to")(a, pyb::tuple(pyb::cast(target)));
      b.step.push_back(std::max(1, core));
    }
    // Contiguous in the output dtype (a no-op for a contiguous array of that dtype).
    if (b.f32)
      b.arrays.push_back(pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>::ensure(a));
    else
      b.arrays.push_back(pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(a));
    if (!b.arrays.back())
      throw pyb::value_error(fmt::format("{}: cannot convert to a float array", args[i].name));
    b.core.push_back(core);
  }
  if (b.f32)
    check_domains<float>(b, args);
  else
    check_domains<double>(b, args);
  return b;
}

pyb::object finish(const pyb::array& out, const Broadcast& b, int core) {
  if (b.all_scalar && core == 0) return out[pyb::tuple()];
  return out;
}

}  // namespace msh::py

PYBIND11_MODULE(_core, m) {
  m.doc() =
      "microshadow._core: the C++ extension of the microshadow package (import microshadow instead). "
      "Vectorized over numpy arrays with ufunc broadcasting; see docs/python.md.";
  // Bad user input (msh::InputError: a value out of its domain, an unknown name, an unreadable file) is a
  // ValueError carrying the CLI's message.
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const msh::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::out_of_range& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.attr("__version__") = MSH_VERSION;
  msh::py::register_micro_shadowing(m);
  msh::py::register_bump(m);
  msh::py::register_microfacet(m);
  msh::py::register_bsdf(m);
  msh::py::register_lut(m);
  msh::py::register_render(m);
  msh::py::register_directional(m);
}
