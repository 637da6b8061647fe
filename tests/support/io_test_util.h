// Helpers for the io tests: deterministic test volumes, scratch directories, and the independent Python
// checker (tests/support/msh_iocheck.py, run with /usr/bin/python3 + numpy).
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <microshadow/io/texture.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

namespace msh::io::test {

inline const char* kPython = "/usr/bin/python3";
inline std::string checker() { return std::string(MSH_SOURCE_DIR) + "/tests/support/msh_iocheck.py"; }

// A fresh empty directory under the build tree, one per test (emptied at the start of each run, kept after it
// for inspection).
inline std::filesystem::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path p = std::filesystem::path(MSH_BINARY_DIR) / "io_test_tmp" /
                            fmt::format("{}.{}", info->test_suite_name(), info->name());
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

// Values in [lo, hi] from a smooth formula, with awkward values planted at the start: exact zero, -0.0, a
// half-float subnormal, 1/3, the range ends.
inline Volume make_volume(int w, int h, int d, int c, float lo, float hi) {
  Volume v(w, h, d, c);
  for (int z = 0; z < d; ++z)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < c; ++k) {
          const double s = std::sin(1.7 * x + 2.3 * y + 0.77 * z + 1.13 * k + 0.1);
          v.at(x, y, z, k) = float(lo + (hi - lo) * (0.5 + 0.5 * s));
        }
  const float special[] = {0.0f, -0.0f, 3.0e-6f, 1.0f / 3.0f, lo, hi, 0.5f, 1.0f};
  for (std::size_t i = 0; i < std::size(special) && i < v.data.size(); ++i) v.data[i] = special[i];
  return v;
}

inline void write_raw(const std::filesystem::path& p, const Volume& v) {
  std::filesystem::remove(p);  // rewriting in place would make ext4 flush (auto_da_alloc)
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(v.data.data()), std::streamsize(v.data.size() * sizeof(float)));
}

// Runs a shell command, returns its exit status and stdout+stderr.
inline int run(const std::string& cmd, std::string* output) {
  std::FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[512];
  output->clear();
  while (std::fgets(buf, sizeof buf, p)) *output += buf;
  const int status = ::pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::string quote(const std::filesystem::path& p) { return fmt::format("'{}'", p.string()); }

// Runs the Python checker: `args` after the subcommand; EXPECTs exit 0 and prints its report otherwise.
inline void python_check(const std::string& args) {
  std::string out;
  const int rc = run(fmt::format("{} {} {}", kPython, checker(), args), &out);
  EXPECT_EQ(rc, 0) << "msh_iocheck.py " << args << "\n" << out;
}

// Collects checker commands and runs them in one Python process (Python + numpy start-up is ~0.1 s of CPU).
class PythonBatch {
 public:
  explicit PythonBatch(std::filesystem::path manifest) : manifest_(std::move(manifest)) {}
  void add(const std::string& args) { lines_ += args + "\n"; }
  void run_all() {
    std::ofstream(manifest_) << lines_;
    python_check(fmt::format("batch {}", quote(manifest_)));
  }

 private:
  std::filesystem::path manifest_;
  std::string lines_;
};

}  // namespace msh::io::test
