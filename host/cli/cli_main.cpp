#include <unistd.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <mutex>

#include "cli.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"
#include "version.hpp"

namespace fracref::cli {

void add_threads_option(CLI::App* sub) {
  sub->add_option_function<int>("--threads", [](const int& n) { set_default_threads(n); },
                                "worker threads (default: every hardware thread; the output does not depend on it)")
      ->check(CLI::PositiveNumber);
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("FRACREF_DATA_DIR")) return env;
  std::error_code ec;
  std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return (ec ? std::filesystem::current_path() : exe.parent_path()) / "data";
}

namespace {
std::mutex g_activity_mutex;
std::string g_activity;
}  // namespace

void set_activity(std::string what) {
  std::lock_guard<std::mutex> lock(g_activity_mutex);
  g_activity = std::move(what);
}

std::string activity() {
  std::lock_guard<std::mutex> lock(g_activity_mutex);
  return g_activity;
}

namespace {
const char* kFooter = R"(Exit codes: 0 success; 1 failure while running; 2 bad input or usage.
Run 'fracref SUBCOMMAND --help' for the options of each subcommand.)";
}

int run(int argc, char** argv) {
  CLI::App app{"fracref: physics-inspired adaptive fracture refinement (Chen et al., SIGGRAPH 2014)",
               "fracref"};
  app.set_version_flag("--version", std::string("fracref ") + kVersion);
  app.footer(kFooter);
  app.require_subcommand(1);
  Action action;
  add_info_command(app, action);
  add_refine_commands(app, action);
  add_bench_command(app, action);
  add_batch_command(app, action);
  add_check_command(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "fracref: " << e.what() << "\n";
    return kExitBadInput;
  }
  return action ? action() : kExitOk;
}

}  // namespace fracref::cli
