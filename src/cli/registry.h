// Command registry for the microshadow CLI.
// Each src/cli/cmd_*.cpp adds its subcommands with MSH_CLI_REGISTER(fn); the CLI executable links every
// src/cli/*.cpp directly (not through a static library), so these static registrars always run.
#pragma once

#include <CLI/CLI.hpp>
#include <microshadow/io/error.h>

#include <functional>
#include <stdexcept>
#include <string>

namespace msh::cli {

// The command groups main() creates before calling the registrars.
struct Groups {
  CLI::App* root = nullptr;  // microshadow
  CLI::App* eval = nullptr;  // microshadow eval <what>
  CLI::App* bake = nullptr;  // microshadow bake <what>
  CLI::App* plot = nullptr;  // microshadow plot <what>  (CSV/PNG figure data)
  CLI::App* verify = nullptr;  // microshadow verify <what>  (as-used accuracy measurements)
};

using Registrar = void (*)(Groups&);

// Returns true so it can initialise a static bool; order of registration = order in --help.
bool add_registrar(Registrar r, int order);
void run_registrars(Groups& g);

// Bad input from the user (domain error, unknown name, unreadable/unwritable file): one line, exit code 2.
using UsageError = ::msh::InputError;

}  // namespace msh::cli

#define MSH_CLI_CONCAT2(a, b) a##b
#define MSH_CLI_CONCAT(a, b) MSH_CLI_CONCAT2(a, b)
// MSH_CLI_REGISTER(fn, order): fn(Groups&) adds subcommands; lower order appears first in --help.
#define MSH_CLI_REGISTER(fn, order) \
  static const bool MSH_CLI_CONCAT(msh_cli_registered_, __LINE__) = ::msh::cli::add_registrar(&(fn), (order))
