// `clothbake lookup-render SCENE.json BAKE_DIR -o out.exr`: renders the scene
// reading the baked lookup with the interpolation the Blender add-on uses
// (bilinear texels, bilinear directions), so bake error is measured without
// Blender and Blender's own error against it.

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/option_range.h"
#include "cli/commands.h"
#include "core/util/hex.h"
#include "cli/memory_budget.h"
#include "cli/thread_limit.h"
#include "core/bake/baker.h"
#include "core/render/renderer.h"
#include "core/util/error.h"
#include "io/atomic_file.h"
#include "io/image_io.h"
#include "io/lookup_io.h"
#include "io/material_io.h"
#include "core/material/material_shader.h"
#include "core/texture/volume_generator.h"
#include "core/weave/cloth_colours.h"
#include "io/progress.h"
#include "io/scene_json.h"
#include "io/system_info.h"

namespace clothbake::cli {

namespace {
struct LookupRenderArgs {
  std::string scene, bake_dir, out_exr, out_png;
  int spp = 0, threads = 0;
  float footprint_scale = 1.0f;
  std::string light_filter = "catmull-rom";
  double memory_gib = 0.0;
  long long seed = -1;
  bool quiet = false;
};

/// The checks of values CLI11 does not make.
void check_lookup_render_args(const LookupRenderArgs& args) {
  if (std::filesystem::path(args.out_exr).extension() != ".exr")
    throw InputError("-o", "the output must be an .exr file, got '" + args.out_exr + "'");
}

/// The scene rendered from a cloth material (a material folder's manifest):
/// every cloth object must be of the material's cloth and optics.
void run_material_render(const LookupRenderArgs& args, Scene& scene, uint64_t budget) {
  io::MaterialInfo info;
  ClothMaterial material = io::read_material(args.bake_dir, info, budget);
  if (args.light_filter == "bilinear") material.light_filter = ClothMaterial::LightFilter::Bilinear;
  if (args.seed >= 0) scene.settings.seed = uint64_t(args.seed);
  std::unique_ptr<Renderer> renderer;
  try {
    // A colour-free material needs of a spec cloth's volume only its
    // thickness (the patches' slab): the colour-free cloth's, the weave's
    // repeat, not the colours' (a 6-colour stripe over a 91-end overshot
    // would otherwise generate 546 ends' cells, 11 GB, for nothing).
    std::vector<std::shared_ptr<const VolumeTexture>> volumes(scene.objects.size());
    if (material.colour_parts())
      for (size_t o = 0; o < scene.objects.size(); ++o)
        if (!scene.objects[o].volume)
          volumes[o] = std::make_shared<const VolumeTexture>(
              generate_volume(colour_free(scene.objects[o].cloth), budget));
    renderer = std::make_unique<Renderer>(scene, budget, volumes);
  } catch (const InputError& e) {
    throw e.in_file(args.scene);
  }
  const ClothScene& prepared = renderer->prepared();
  const std::string manifest = args.bake_dir + "/manifest.json";
  for (int o = 0; o < prepared.object_count(); ++o) {
    try {
      check_material_fits(prepared, o, material);
    } catch (const InputError& e) {
      throw InputError(e.field(), e.message() + " (material " + manifest + ", baked from '" +
                                      info.cloth_name + "')",
                       args.scene);
    }
  }
  const std::vector<const ClothMaterial*> materials(size_t(prepared.object_count()), &material);
  MaterialLookupSettings lookup;
  lookup.footprint_scale = args.footprint_scale;
  const SurfaceShader shader = material_shader(prepared, materials, lookup);
  io::ProgressBar bar("lookup-render", args.quiet);
  const Image image = renderer->render_with(&shader, [&](double f) { bar.update(f); });
  bar.finish();
  io::write_render_images(args.out_exr, args.out_png, image);
  if (!args.quiet)
    std::fprintf(stderr, "lookup-render: material, pixel loop %.3f s, setup %.3f s\n",
                 renderer->stats().render_seconds, renderer->stats().setup_seconds);
}

void run_lookup_render(const LookupRenderArgs& args) {
  const auto threads = limit_threads(args.threads);
  // Step 1: everything is read and checked before any work or output.
  io::check_output_folder(args.out_exr, "-o");
  if (!args.out_png.empty()) io::check_output_folder(args.out_png, "--png");
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  Scene scene = io::load_scene(args.scene, budget);
  if (args.spp > 0) scene.settings.spp = args.spp;
  try {
    check_render_memory(scene.camera, budget);
  } catch (const InputError& e) {
    throw e.in_file(args.scene);
  }
  if (io::is_material_folder(args.bake_dir)) return run_material_render(args, scene, budget);
  io::LookupInfo info;
  const std::vector<LookupTable> tables =
      io::read_lookup(args.bake_dir, info, io::scene_fingerprint(scene));
  // The pixel-sampling seed only: set after the lookup's scene check, since
  // the scene's seed is part of the hash (it seeds the bake's jitter too).
  if (args.seed >= 0) scene.settings.seed = uint64_t(args.seed);
  std::unique_ptr<Renderer> renderer;
  try {
    renderer = std::make_unique<Renderer>(scene, budget);
  } catch (const InputError& e) {
    throw e.in_file(args.scene);
  }
  // Step 2: the lookup must be of this scene's meshes and volumes (the scene
  // hash covers the specs; a volume generator of another version does not).
  const std::string manifest = args.bake_dir + "/manifest.json";
  if (int(tables.size()) != renderer->prepared().object_count())
    throw InputError("objects",
                     "the lookup has " + std::to_string(tables.size()) + " objects, the scene " +
                         std::to_string(renderer->prepared().object_count()),
                     manifest);
  for (int o = 0; o < renderer->prepared().object_count(); ++o) {
    const std::string field = "objects[" + std::to_string(o) + "]";
    if (tables[o].quad_count() != renderer->prepared().quad_count(o))
      throw InputError(field + ".quads",
                       "the lookup has " + std::to_string(tables[o].quad_count()) +
                           " quads, the scene's mesh " +
                           std::to_string(renderer->prepared().quad_count(o)) + "; bake again",
                       manifest);
    const std::string hex = hex16(renderer->prepared().volume(o).content_hash());
    if (!info.cloth_hashes[o].empty() && info.cloth_hashes[o] != hex)
      throw InputError(field + ".cloth_hash",
                       "the lookup was baked from a volume with hash " + info.cloth_hashes[o] +
                           ", this scene's cloth gives " + hex +
                           " (another cloth or another clothbake version); bake again",
                       manifest);
  }
  std::atomic<uint64_t> misses{0};
  const SurfaceShader shader = lookup_shader(renderer->prepared(), tables, &misses);
  io::ProgressBar bar("lookup-render", args.quiet);
  const Image image = renderer->render_with(&shader, [&](double f) { bar.update(f); });
  bar.finish();
  io::write_render_images(args.out_exr, args.out_png, image);
  if (misses > 0)
    std::fprintf(stderr,
                 "lookup-render: %llu lookups fell on quads or directions the bake did not "
                 "compute (rendered transparent); bake with this camera or a full bake\n",
                 (unsigned long long)misses.load());
}
}  // namespace

void register_lookup_render_command(CLI::App& app, Action action) {
  auto args = std::make_shared<LookupRenderArgs>();
  CLI::App* cmd =
      app.add_subcommand("lookup-render", "Render a scene from its baked lookup (no volumes)");
  cmd->add_option("scene", args->scene, "scene JSON")->required();
  cmd->add_option("bake", args->bake_dir, "bake folder (clothbake bake -o)")->required();
  cmd->add_option("-o,--out", args->out_exr, "output EXR (linear RGBA, float)")->required();
  cmd->add_option("--png", args->out_png, "also write an sRGB PNG preview");
  cmd->add_option("--spp", args->spp, "samples per pixel (overrides the scene)")
      ->check(in_range(1, 65536));
  cmd->add_option("--seed", args->seed,
                  "seed of the pixel sampling (default: the scene's); the bake's seed is its own")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--footprint-scale", args->footprint_scale,
                  "material only: the lookup's footprint relative to the pixel's stratum (pixel / sqrt(spp))")
      ->check(in_range(0.0, 16.0))
      ->capture_default_str();
  cmd->add_option("--light-filter", args->light_filter,
                  "material only: interpolation between light nodes")
      ->check(CLI::IsMember({"catmull-rom", "bilinear"}))
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(in_range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->callback([args, action] {
    check_lookup_render_args(*args);
    if (action == Action::Run) run_lookup_render(*args);
  });
}

}  // namespace clothbake::cli
