#include "cli/app.h"

#include <CLI/CLI.hpp>

#include "core/util/error.h"

namespace clothbake::cli {

int run_cli(int argc, const char* const* argv, Action action, std::ostream& out,
            std::ostream& err) {
  CLI::App app{"clothbake: woven cloth from a volume texture (Kimoto & Ohno, c. 1990)"};
  app.require_subcommand(1);
  register_volume_command(app, action);
  register_draft_command(app, action);
  register_fiber_command(app, action);
  register_render_command(app, action);
  register_compare_command(app, action);
  register_merge_command(app, action);
  register_bake_command(app, action);
  register_lookup_render_command(app, action);
  register_material_command(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version succeed; a bad argument is an error like any other
    // (one line naming the option, exit status 1), not CLI11's own codes.
    if (e.get_exit_code() == 0) return app.exit(e, out, err);
    err << "clothbake: error: " << e.what() << "\nRun with --help for more information.\n";
    return 1;
  } catch (const InputError& e) {
    err << "clothbake: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace clothbake::cli
