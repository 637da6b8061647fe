// Measured errors against stated bounds, for tests that compare many functions with their references
// (tests/test_shader_portable_cpp.cpp): a Family of checks, each row checked and the family printed on one
// line, and the check that a clamped input set to NaN gives the value at the input's lower bound.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

namespace msh::test {

// One family of checks: rows of a measured value and its bound, each checked when the family goes out of
// scope (value <= bound; at_least rows, the inputs' coverage: value >= bound) and printed on one line
// "[ cpp ] title: name value [bound], ...". max rows keep the largest error (a NaN sticks), count rows count.
struct Family {
  struct Row {
    const char* name;
    double bound, value;
    bool min;
  };
  std::string title;
  std::vector<Row> rows;
  explicit Family(const char* t) : title(t) {}
  Family(const Family&) = delete;
  ~Family() {
    std::printf("[ cpp ] %s:", title.c_str());
    for (const Row& r : rows) {
      EXPECT_TRUE(r.min ? r.value >= r.bound : r.value <= r.bound)
          << title << ": " << r.name << " " << r.value << (r.min ? " < " : " > ") << r.bound;
      const bool whole = r.value == std::floor(r.value) && r.value < 1e9;
      std::printf(whole ? "%s %s %.0f [%s%g]" : "%s %s %.2e [%s%g]", &r == &rows[0] ? "" : ",", r.name,
                  r.value, r.min ? ">= " : "", r.bound);
    }
    std::printf("\n");
  }
  Row& row(const char* name, double bound, bool min) {
    for (Row& r : rows)
      if (std::strcmp(r.name, name) == 0) return r;
    return rows.emplace_back(Row{name, bound, 0.0, min});
  }
  void max(const char* name, double bound, double e) {
    Row& r = row(name, bound, false);
    if (!(e <= r.value)) r.value = e;
  }
  void diff(const char* name, double bound, double a, double b) { max(name, bound, std::abs(a - b)); }
  void count(const char* name, double bound, bool hit) { row(name, bound, false).value += hit; }
  void eq(const char* name, double a, double b) { count(name, 0, !(a == b)); }
  void at_least(const char* name, double bound, double hits) { row(name, bound, true).value += hits; }
};

// f(args) with one clamped input at a time set to NaN must be finite and equal f with that input at its
// lower bound lo[k] (NaN in lo: not a clamped input). Returns the number of violations.
template <class F, std::size_t N>
int nan_clamp_violations(F f, const float (&args)[N], const float (&lo)[N]) {
  int bad = 0;
  for (std::size_t k = 0; k < N; ++k) {
    if (std::isnan(lo[k])) continue;
    std::array<float, N> a, b;
    std::copy(args, args + N, a.begin());
    b = a, a[k] = std::numeric_limits<float>::quiet_NaN(), b[k] = lo[k];
    const float fa = std::apply(f, a), fb = std::apply(f, b);
    bad += !(std::isfinite(fa) && fa == fb);
  }
  return bad;
}

}  // namespace msh::test
