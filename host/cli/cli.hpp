#pragma once
// The CLI's entry point and the subcommands it dispatches to (one file per subcommand).
#include <filesystem>
#include <functional>
#include <string>

namespace CLI {
class App;
}

namespace fracref::cli {

/// Parses argv and runs the chosen subcommand. \return the process exit code.
/// \throw InputError for bad input (exit 2), other exceptions for failures (exit 1).
int run(int argc, char** argv);

/// What a subcommand does once its options are parsed; returns the exit code.
using Action = std::function<int()>;

/// Each adds its subcommand to `app` and stores in `action` what to run when it is chosen.
void add_info_command(CLI::App& app, Action& action);
void add_refine_commands(CLI::App& app, Action& action);  // refine and demo
void add_bench_command(CLI::App& app, Action& action);
void add_batch_command(CLI::App& app, Action& action);
void add_check_command(CLI::App& app, Action& action);

/// Adds `--threads N` to `sub`: the worker threads of everything the command runs
/// (set_default_threads); without it, every hardware thread.
void add_threads_option(CLI::App* sub);

/// True when stderr is a terminal: progress lines are shown only then.
bool stderr_is_terminal();

/// Where set-up put the data the demos need (the npm bunny): $FRACREF_DATA_DIR, else the folder
/// `data` beside the executable.
std::filesystem::path data_dir();

/// Records what the CLI is doing ("reading the scene file", "the refine stage"), for the one
/// message main() prints when memory runs out. Thread-safe.
void set_activity(std::string what);
/// The last activity set; empty before the first.
std::string activity();

}  // namespace fracref::cli
