// `clothbake render SCENE.json -o out.exr`: the reference renderer
// (PAPER.md s.4-5): linear RGBA EXR, sRGB PNG preview, progress on stderr.

#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/option_range.h"
#include "cli/commands.h"
#include "cli/memory_budget.h"
#include "cli/thread_limit.h"
#include "core/render/renderer.h"
#include "core/util/error.h"
#include "io/atomic_file.h"
#include "io/image_io.h"
#include "io/progress.h"
#include "io/scene_json.h"
#include "io/system_info.h"

namespace clothbake::cli {

namespace {

struct RenderArgs {
  std::string scene;
  std::string out_exr;
  std::string out_png;
  int spp = 0;
  int threads = 0;
  double memory_gib = 0.0;
  bool quiet = false;
  bool stats_json = false;
};

/// The checks of values CLI11 does not make.
void check_render_args(const RenderArgs& args) {
  const std::string ext = std::filesystem::path(args.out_exr).extension().string();
  if (ext != ".exr")
    throw InputError("-o", "the output must be an .exr file, got '" + args.out_exr + "'");
}

void run_render(const RenderArgs& args) {
  const auto threads = limit_threads(args.threads);
  // Step 1: everything is read and checked before any work or output.
  io::check_output_folder(args.out_exr, "-o");
  if (!args.out_png.empty()) io::check_output_folder(args.out_png, "--png");
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  Scene scene = io::load_scene(args.scene, budget);
  if (args.spp > 0) scene.settings.spp = args.spp;
  std::unique_ptr<Renderer> renderer;
  try {
    check_render_memory(scene.camera, budget);
    renderer = std::make_unique<Renderer>(scene, budget);
  } catch (const InputError& e) {
    throw e.in_file(args.scene);
  }
  // Step 2: the render, then both images or neither.
  io::ProgressBar bar("render", args.quiet);
  const Image image = renderer->render([&](double f) { bar.update(f); });
  bar.finish();
  io::write_render_images(args.out_exr, args.out_png, image);
  const RenderStats& st = renderer->stats();
  if (args.stats_json) {
    const nlohmann::json j = {{"scene", args.scene},
                              {"width", image.width},
                              {"height", image.height},
                              {"spp", scene.settings.spp},
                              {"setup_seconds", st.setup_seconds},
                              {"render_seconds", st.render_seconds},
                              {"camera_rays", st.camera_rays},
                              {"march_samples", st.march_samples}};
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!args.quiet) {
    std::fprintf(stderr, "setup %.3fs, render %.3fs, %llu march samples (%.1f M/s)\n",
                 st.setup_seconds, st.render_seconds, (unsigned long long)st.march_samples,
                 st.render_seconds > 0 ? st.march_samples / st.render_seconds * 1e-6 : 0.0);
  }
}

}  // namespace

void register_render_command(CLI::App& app, Action action) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene with the reference ray-marcher");
  cmd->add_option("scene", args->scene, "scene JSON")->required();
  cmd->add_option("-o,--out", args->out_exr, "output EXR (linear RGBA, float)")->required();
  cmd->add_option("--png", args->out_png, "also write an sRGB PNG preview");
  cmd->add_option("--spp", args->spp, "samples per pixel (overrides the scene)")
      ->check(in_range(1, 65536));
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(in_range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--stats", args->stats_json, "print timing statistics as JSON on stdout");
  cmd->callback([args, action] {
    check_render_args(*args);
    if (action == Action::Run) run_render(*args);
  });
}

}  // namespace clothbake::cli
