#pragma once
/// The whole command line: every subcommand registered on one CLI11 app,
/// parsed, and its callback run. main.cpp and the argument fuzz target
/// (tests/fuzz/cli_args_fuzz.cpp) both come through here.

#include <ostream>

#include "cli/commands.h"

namespace clothbake::cli {

/// Parses argv (argv[0] is the program name) and runs the chosen command's
/// callback with `action`. Returns the exit status: 0 (--help and --version
/// included, CLI11's text on `out`), or 1 for a usage error (CLI::ParseError,
/// printed on `err` as "clothbake: error: OPTION: message" and a line naming
/// --help) or an InputError (printed on `err` as "clothbake: error: FILE:
/// FIELD: message"). Any other exception propagates (main reports it).
int run_cli(int argc, const char* const* argv, Action action, std::ostream& out, std::ostream& err);

}  // namespace clothbake::cli
