// clothbake: command-line entry point. Errors from bad input arrive as
// exceptions and leave here as one line on stderr and exit code 1; an
// interrupt (SIGTERM, SIGINT) removes unfinished outputs (cli/interrupt.h).

#include <cstdio>
#include <exception>
#include <iostream>

#include "cli/app.h"
#include "cli/interrupt.h"

int main(int argc, char** argv) {
  clothbake::cli::install_interrupt_handler();
  try {
    return clothbake::cli::run_cli(argc, argv, clothbake::cli::Action::Run, std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << "clothbake: error: " << e.what() << "\n";
    return 1;
  }
}
