// The fracref command-line tool: parses the command line and maps errors to exit codes.
#include <iostream>

#include "cli.hpp"
#include "util/error.hpp"

int main(int argc, char** argv) {
  try {
    return fracref::cli::run(argc, argv);
  } catch (const fracref::InputError& e) {
    std::cerr << "fracref: " << e.what() << "\n";
    return fracref::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "fracref: " << e.what() << "\n";
    return fracref::kExitFailure;
  }
}
