#pragma once
// `vpcontact converge CASE`: convergence studies of the scheme (Theorem 3.5) and
// the agreement of the two solvers; see docs/verification.md.
#include <CLI/CLI.hpp>

namespace vpc {

/// Adds the `converge` subcommand to `app` and returns it.
CLI::App* add_converge_command(CLI::App& app);
/// Runs the study the parsed options describe; returns the exit code. Throws
/// vpc::Error for bad input.
int run_converge_command();

}  // namespace vpc
