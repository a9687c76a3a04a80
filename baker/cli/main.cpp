// clothbake: command-line entry point. Errors from bad input arrive as
// exceptions and leave here as one line on stderr and exit code 1.

#include <cstdio>
#include <exception>
#include <iostream>

#include "cli/app.h"

int main(int argc, char** argv) {
  try {
    return clothbake::cli::run_cli(argc, argv, clothbake::cli::Action::Run, std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << "clothbake: error: " << e.what() << "\n";
    return 1;
  }
}
