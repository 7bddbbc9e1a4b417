#pragma once
// The CLI's entry point and the subcommands it dispatches to.
namespace fracref::cli {
/// Parses argv and runs the chosen subcommand. \return the process exit code.
/// \throw InputError for bad input (exit 2), other exceptions for failures (exit 1).
int run(int argc, char** argv);
}  // namespace fracref::cli
