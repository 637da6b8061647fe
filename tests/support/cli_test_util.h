// Helpers shared by the CLI tests: run the microshadow executable the tests were built with (MSH_CLI_PATH)
// and capture its exit code and output; per-test scratch directories; reading a file whole.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>

namespace msh::test {

struct CliResult {
  int code;  // the exit code; −1 if the process did not exit normally
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A fresh, empty directory for the running test: MSH_BINARY_DIR/<area>/<test name>.<pid>.
inline std::filesystem::path scratch_dir(const std::string& area) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path p = std::filesystem::path(MSH_BINARY_DIR) / area /
                            (std::string(info ? info->name() : "none") + "." + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

// A fixture with a fresh, empty scratch directory `dir` for each test (scratch_dir(area)), removed after it.
class ScratchDirTest : public ::testing::Test {
 protected:
  explicit ScratchDirTest(std::string area) : area_(std::move(area)) {}
  void SetUp() override { dir = scratch_dir(area_); }
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::filesystem::path dir;

 private:
  std::string area_;
};

// Runs `microshadow ARGS`, stdout and stderr captured through files in `dir`.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd =
      std::string(MSH_CLI_PATH) + " " + args + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

// The same, capturing through a per-process directory under the temporary directory.
inline CliResult run_cli(const std::string& args) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("msh_cli_test." + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return run_cli(args, dir);
}

}  // namespace msh::test
