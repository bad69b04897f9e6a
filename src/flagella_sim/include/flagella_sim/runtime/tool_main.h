// The error handling every command-line tool shares, so that no exception ever escapes main
// ("terminate called ...") and the exit code says what went wrong (README, exit codes).
#pragma once

#include <CLI/CLI.hpp>
#include <exception>
#include <functional>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/solver/solver_failure.h"

namespace flagella::cli {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;        ///< anything else (a file that cannot be written, ...)
constexpr int kExitBadInput = 2;       ///< bad arguments or input: the message names the field
constexpr int kExitSolverFailure = 3;  ///< Newton failed for good (outputs up to it are kept)

/// Parses the command line: nothing to return if the tool should go on; 0 after --help (usage
/// printed), 2 after a bad or unknown argument (the message names it). Replaces CLI11_PARSE,
/// whose exit codes for argument errors are CLI11's own (105-113).
inline std::optional<int> parseArguments(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::Success&) {  // an option that answered and ends the tool (--list-gains)
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << "error: " << e.what() << " (--help for the usage)\n";
    return kExitBadInput;
  }
  return std::nullopt;
}

/// Runs a tool's work (after its arguments are parsed, CLI11 having answered --help) and turns
/// what it throws into a message on stderr and an exit code: invalid input (ConfigError, and
/// any std::invalid_argument, or an InputFileError) 2, a solver failure 3, any other exception 1.
inline int runGuarded(const std::function<int()>& body) {
  try {
    return body();
  } catch (const std::invalid_argument& e) {  // ConfigError and DataError included
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const InputFileError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const SolverFailure& e) {
    std::cerr << "error: solver failure: " << e.what() << "\n";
    return kExitSolverFailure;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitFailure;
  } catch (...) {
    std::cerr << "error: unknown exception\n";
    return kExitFailure;
  }
}

}  // namespace flagella::cli
