#pragma once
/// Each subcommand of the `clothbake` program registers itself here. A command
/// parses its arguments and calls the io and core libraries, nothing more.

namespace CLI {
class App;
}

namespace clothbake::cli {

/// What a command's callback does once CLI11 has parsed its options.
enum class Action {
  Run,        ///< check the values, then read, compute and write (the program)
  ParseOnly,  ///< check the values (the same checks), touch no file (tests/fuzz/)
};

void register_volume_command(CLI::App& app, Action action);
void register_draft_command(CLI::App& app, Action action);
void register_fiber_command(CLI::App& app, Action action);
void register_render_command(CLI::App& app, Action action);
void register_compare_command(CLI::App& app, Action action);
void register_merge_command(CLI::App& app, Action action);
void register_bake_command(CLI::App& app, Action action);
void register_lookup_render_command(CLI::App& app, Action action);
void register_material_command(CLI::App& app, Action action);

}  // namespace clothbake::cli
