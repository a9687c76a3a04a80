#pragma once
/// Each subcommand of the `clothbake` program registers itself here. A command
/// parses its arguments and calls the io and core libraries, nothing more.

namespace CLI {
class App;
}

namespace clothbake::cli {

void register_volume_command(CLI::App& app);
void register_fiber_command(CLI::App& app);
void register_render_command(CLI::App& app);
void register_compare_command(CLI::App& app);
void register_merge_command(CLI::App& app);
void register_bake_command(CLI::App& app);
void register_lookup_render_command(CLI::App& app);

}  // namespace clothbake::cli
