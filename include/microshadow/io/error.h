// Error types shared by the library and the CLI.
#pragma once

#include <stdexcept>

namespace msh {

// Bad input from a user: a parameter outside its domain, a malformed or unreadable file, an unwritable path.
// The CLI reports it in one line and exits with code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace msh
