// Subcommands whose work lands with later issues: they exist with their help text and say
// plainly that they are not implemented yet.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli.hpp"
#include "util/error.hpp"

namespace fracref::cli {
namespace {

Action not_yet(const std::string& what) {
  return [what] {
    std::cerr << "fracref: '" << what << "' is not implemented yet in this version\n";
    return int(kExitFailure);
  };
}

}  // namespace

void add_check_command(CLI::App& app, Action& action) {
  CLI::App* sub = app.add_subcommand("check", "Re-verify an output folder (closed, manifold, partition, frames)");
  sub->allow_extras();
  sub->callback([&action] { action = not_yet("check"); });
}

}  // namespace fracref::cli
