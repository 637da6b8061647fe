// The exit codes of the project's command-line tools (microshadow, tools/research's microshadow_research),
// written once.
#pragma once

#include <microshadow/io/error.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <string>

namespace msh::cli {

// Parses argv into `app` and runs the chosen subcommand's callback. Returns the process's exit code: 0 after
// success, --help or --version; 2 after a usage error or bad input ("<program>: error: ..." on stderr, one
// line); 1 after any other failure ("<program>: failed: ...").
inline int parse_and_run(CLI::App& app, int argc, char** argv, const std::string& program) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << program << ": error: " << e.what() << " (see --help)" << std::endl;
    return 2;
  } catch (const InputError& e) {
    std::cerr << program << ": error: " << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << program << ": failed: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}

}  // namespace msh::cli
