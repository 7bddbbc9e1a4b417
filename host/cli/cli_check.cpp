// `fracref check OUT`: re-verifies an output folder with the strict readers.
#include <CLI/CLI.hpp>
#include <iostream>

#include "check/check_output.hpp"
#include "cli.hpp"
#include "util/error.hpp"

namespace fracref::cli {
namespace {

struct CheckCliOptions {
  std::string folder;
  bool json = false;
};

int run_check(const CheckCliOptions& o) {
  CheckReport report = check_output(o.folder);
  if (o.json) {
    std::cout << check_report_json(report).dump(2) << "\n";
  } else {
    for (const CheckResult& c : report.checks)
      std::cout << "  " << check_status_name(c.status) << "  " << c.name << ": " << c.detail << "\n";
    for (const std::string& f : report.failures) std::cerr << "fracref: check: " << o.folder << "/" << f << "\n";
    std::cout << (report.ok() ? "ok" : "FAILED") << "\n";
  }
  return report.exit_code();
}

}  // namespace

void add_check_command(CLI::App& app, Action& action) {
  auto opts = std::make_shared<CheckCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "check", "Re-verify an output folder: pieces closed, manifold, outward, intersection-free, partition, frames, glb");
  sub->add_option("folder", opts->folder, "output folder written by refine or demo")->required();
  sub->add_flag("--json", opts->json, "print one JSON object");
  add_threads_option(sub);
  sub->footer("Exit codes: 0 every check passed; 1 a check failed (each failure names the piece or frame);\n"
              "2 the folder is not a fracref output or a file in it cannot be read.");
  sub->callback([opts, &action] { action = [opts] { return run_check(*opts); }; });
}

}  // namespace fracref::cli
