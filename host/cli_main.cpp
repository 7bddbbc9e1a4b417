#include <CLI/CLI.hpp>
#include <iostream>

#include "cli.hpp"
#include "util/error.hpp"
#include "version.hpp"

namespace fracref::cli {

int run(int argc, char** argv) {
  CLI::App app{"fracref: physics-inspired adaptive fracture refinement"};
  app.set_version_flag("--version", std::string("fracref ") + kVersion);
  app.require_subcommand(1);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  return kExitOk;
}

}  // namespace fracref::cli
