// The ganzfeld command as a function: main() is run_cli(argc, argv); the command-line fuzzer
// (fuzz/) calls it with parse_only, which parses and validates the arguments but runs no action
// (actions write files or run long).
#pragma once

namespace ganzfeld::cli {

/// Parses argv and runs the selected sub-command; returns the exit code:
/// 0 ok, 2 bad input (one line on stderr), 1 internal failure. With `parse_only`, stops after
/// parsing: 0 when a sub-command was selected, 2 (or CLI11's code for --help) otherwise.
int run_cli(int argc, const char* const* argv, bool parse_only = false);

}  // namespace ganzfeld::cli
