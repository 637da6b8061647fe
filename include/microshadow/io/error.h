// Error types (and the range check) shared by the library, the CLI and the Python module.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace msh {

// Bad input from a user: a parameter outside its domain, a malformed or unreadable file, an unwritable path.
// The CLI reports it in one line and exits with code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws InputError("<what> must be in [lo, hi], got <v>") unless lo <= v <= hi (NaN fails). The one range
// check of the CLI, the Python module and the BRDF registry, so all three word it the same way.
void require_range(double v, double lo, double hi, const std::string& what);

// Every reader calls this before opening `path` for reading: InputError "'<path>': <what>is not a regular
// file (<kind>); refused before opening" when the path (symlinks followed) exists and is a FIFO, socket,
// device or directory (a FIFO would block the open, /dev/zero would be read without end). A missing path
// passes, so that the caller's own "cannot open" / "not found" message stays as it was.
void require_regular_file(const std::filesystem::path& path, const std::string& what = "");

}  // namespace msh
