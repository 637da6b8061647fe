// Shared machinery of the Python module: ufunc-like broadcasting of numpy arguments, the dtype rule, and
// parallel element loops (oneTBB) with deterministic error reporting.
//
// dtype rule (docs/python.md): the result is float32 when at least one argument is a float32 (or float16)
// array and none is a float64 / integer / bool array; otherwise float64. Python scalars do not vote (as in
// numpy's value-based casting). Integer and bool arrays are converted to float64; complex, object, string and
// other dtypes raise ValueError. Every kernel computes in double (the CLI's precision) and rounds the result
// once to the output dtype, so a float32 result is the CLI's double value at the same (float32) inputs,
// correctly rounded.
#pragma once

#include <microshadow/io/error.h>
#include <microshadow/math/vec.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace msh::py {

namespace pyb = pybind11;

// The domain of an argument's values, checked for every element by broadcast() (docs/python.md, "Errors"):
//   Finite     every number finite (the default: an argument a function does not declare is still checked);
//   Direction  a 3-vector of finite numbers, not all zero (the CLI's "non-zero vector");
//   Uniform    every number in [0, 1) (sample_vndf / sample_brdf's u);
//   Checked    the kernel range-checks every element itself with the CLI's message (NaN fails), e.g.
//              require_range on alpha or the micro-shadowing registry's inputs.
enum class Domain { Finite, Direction, Uniform, Checked };

// An argument: a Python object plus its core dimension (0: one number per element, 3: a 3-vector per
// element, the last axis) and the domain of its values.
struct ArgSpec {
  pyb::handle obj;
  const char* name;
  int core = 0;
  Domain domain = Domain::Finite;
};

// Arguments broadcast against each other (core dimensions excluded), converted to one dtype, C-contiguous.
struct Broadcast {
  bool f32 = false;
  std::vector<pyb::ssize_t> shape;   // broadcast shape (without core dimensions)
  std::size_t n = 1;                 // elements of the broadcast shape
  std::vector<pyb::array> arrays;    // per argument: either `core` numbers (broadcast) or n·core numbers
  std::vector<std::ptrdiff_t> step;  // per argument: 0 (broadcast) or core (one per element)
  std::vector<int> core;
  bool all_scalar = true;  // every argument was a 0-d array or a Python scalar (result: a numpy scalar)

  template <class T>
  const T* data(std::size_t i) const {
    return static_cast<const T*>(arrays[i].data());
  }
};

// Builds the Broadcast for `args`; raises ValueError (pybind11::value_error) on a shape mismatch, a missing
// core dimension or an unsupported dtype, and InputError (ValueError) on a value outside its argument's
// Domain: the message names the argument, the value and the element of the LOWEST index (ties: the first
// argument), so it does not depend on the thread count. An optional `force_f64` forces float64 output.
Broadcast broadcast(const std::vector<ArgSpec>& args, bool force_f64 = false);

// A new C-contiguous output array of the broadcast shape plus `core` trailing elements (0: none).
template <class T>
pyb::array_t<T> make_output(const Broadcast& b, int core = 0) {
  std::vector<pyb::ssize_t> s = b.shape;
  if (core > 0) s.push_back(core);
  return pyb::array_t<T>(s);
}

// A numpy scalar for a 0-d result (as ufuncs return), else the array itself.
pyb::object finish(const pyb::array& out, const Broadcast& b, int core = 0);

// Runs body(begin, end) over [0, n) in chunks, in parallel when n is large (oneTBB; each element is
// independent, so the result does not depend on the thread count). The GIL must be released by the caller.
template <class Body>
void parallel_chunks(std::size_t n, Body&& body) {
  constexpr std::size_t kGrain = 16384;
  if (n <= kGrain) {
    if (n) body(std::size_t(0), n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

// Runs f(i) for every element; when f throws for some elements, the exception of the LOWEST failing index is
// rethrown (deterministic whatever the thread count and the scheduling).
template <class F>
void parallel_each(std::size_t n, F&& f) {
  std::atomic<std::size_t> first_bad{std::numeric_limits<std::size_t>::max()};
  parallel_chunks(n, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (i > first_bad.load(std::memory_order_relaxed)) return;
      try {
        f(i);
      } catch (...) {
        std::size_t cur = first_bad.load();
        while (i < cur && !first_bad.compare_exchange_weak(cur, i)) {
        }
        return;
      }
    }
  });
  const std::size_t bad = first_bad.load();
  if (bad != std::numeric_limits<std::size_t>::max()) f(bad);  // rethrows that element's error
}

// The i-th element's k-th component of argument a.
template <class T>
inline double at(const Broadcast& b, std::size_t a, std::size_t i, int k = 0) {
  return double(b.data<T>(a)[std::ptrdiff_t(i) * b.step[a] + k]);
}

// Reads argument a of element i (component k) as double, whatever the array dtype T. Holds its own copy of
// the pointers and steps, so that a copy local to a loop is not reloaded after every opaque call.
template <class T>
struct Reader {
  static constexpr std::size_t kMaxArgs = 8;
  const T* p[kMaxArgs] = {};
  std::ptrdiff_t s[kMaxArgs] = {};
  explicit Reader(const Broadcast* b) {
    if (b->arrays.size() > kMaxArgs) throw std::logic_error("Reader: too many arguments");
    for (std::size_t a = 0; a < b->arrays.size(); ++a) p[a] = b->data<T>(a), s[a] = b->step[a];
  }
  double operator()(std::size_t a, std::size_t i, int k = 0) const {
    return double(p[a][std::ptrdiff_t(i) * s[a] + k]);
  }
  Vec3d vec(std::size_t a, std::size_t i) const {
    const T* q = p[a] + std::ptrdiff_t(i) * s[a];
    return {double(q[0]), double(q[1]), double(q[2])};
  }
};

// out[i] = f(reader, i) for every element of the broadcast shape, in the broadcast dtype, with the GIL
// released and in parallel; f is called for both dtypes (a generic lambda).
template <class F>
pyb::object map_scalar(const Broadcast& b, F&& f) {
  auto run = [&](auto tag) -> pyb::object {
    using T = decltype(tag);
    pyb::array_t<T> out = make_output<T>(b);
    T* o = out.mutable_data();
    const Reader<T> r(&b);
    {
      pyb::gil_scoped_release release;
      parallel_each(b.n, [&](std::size_t i) { o[i] = T(f(r, i)); });
    }
    return finish(out, b);
  };
  return b.f32 ? run(float{}) : run(double{});
}

// The same for a 3-vector per element (output shape: broadcast shape + (3,)).
template <class F>
pyb::object map_vec3(const Broadcast& b, F&& f) {
  auto run = [&](auto tag) -> pyb::object {
    using T = decltype(tag);
    pyb::array_t<T> out = make_output<T>(b, 3);
    T* o = out.mutable_data();
    const Reader<T> r(&b);
    {
      pyb::gil_scoped_release release;
      parallel_each(b.n, [&](std::size_t i) {
        const Vec3d v = f(r, i);
        o[3 * i] = T(v.x), o[3 * i + 1] = T(v.y), o[3 * i + 2] = T(v.z);
      });
    }
    return finish(out, b, 3);
  };
  return b.f32 ? run(float{}) : run(double{});
}

// The CLI's range check and message ("<what> must be in [lo, hi], got v"; NaN fails; io/error.h), raised as
// a ValueError.
using ::msh::require_range;

// Whether `obj` is None.
inline bool is_none(pyb::handle obj) { return obj.is_none(); }

// The Python value (dicts, lists, numbers, strings) of the JSON text `text`, through the json module.
inline pyb::object json_to_python(const std::string& text) {
  return pyb::module_::import("json").attr("loads")(text);
}

// Registration of each part of the module (one per source file).
void register_micro_shadowing(pyb::module_& m);
void register_bump(pyb::module_& m);
void register_microfacet(pyb::module_& m);
void register_bsdf(pyb::module_& m);
void register_lut(pyb::module_& m);
void register_render(pyb::module_& m);
void register_directional(pyb::module_& m);

}  // namespace msh::py
