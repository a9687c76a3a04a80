// clothbake: command-line entry point. Errors from bad input arrive as
// exceptions and leave here as one line on stderr and exit code 1; an
// interrupt (SIGTERM, SIGINT) removes unfinished outputs (cli/interrupt.h).

#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "cli/interrupt.h"
#include "core/error.h"

int main(int argc, char** argv) {
  clothbake::cli::install_interrupt_handler();
  CLI::App app{"clothbake: woven cloth from a volume texture (Kimoto & Ohno, c. 1990)"};
  app.require_subcommand(1);
  clothbake::cli::register_volume_command(app);
  clothbake::cli::register_fiber_command(app);
  clothbake::cli::register_render_command(app);
  clothbake::cli::register_compare_command(app);
  clothbake::cli::register_merge_command(app);
  clothbake::cli::register_bake_command(app);
  clothbake::cli::register_lookup_render_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version succeed; a bad argument is an error like any other
    // (one line naming the option, exit status 1), not CLI11's own codes.
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "clothbake: error: %s\nRun with --help for more information.\n", e.what());
    return 1;
  } catch (const clothbake::InputError& e) {
    std::fprintf(stderr, "clothbake: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clothbake: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
