// `clothbake material SPEC_OR_SCENE.json -o DIR`: bake a cloth material, the
// appearance of one weave repeat for every view and light direction and every
// distance (docs/material-format.md), which lookup-render applies to any
// scene whose cloth matches.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/memory_budget.h"
#include "cli/thread_limit.h"
#include "core/material/material_bake.h"
#include "core/material/material_shader.h"
#include "core/scene/cloth_scene.h"
#include "core/texture/volume_generator.h"
#include "core/util/error.h"
#include "core/util/random.h"
#include <tbb/global_control.h>

#include "io/atomic_file.h"
#include "io/cloth_spec_json.h"
#include "io/json_reader.h"
#include "io/material_io.h"
#include "io/progress.h"
#include "io/scene_json.h"
#include "io/text_file.h"

namespace clothbake::cli {

namespace {
struct MaterialArgs {
  std::string input, out_dir, object, light_map = "horizon";
  MaterialSettings settings;
  float depth_scale = 0.0f;  // 0: the scene object's, or 1 for a spec
  int threads = 0;
  double memory_gib = 0.0;
  long long seed = -1;
  bool quiet = false;
};

std::string hex16(uint64_t h) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)h);
  return hex;
}

// About 80 lines: read and check, bake, write; as each command reads.
void run_material(const MaterialArgs& args) {
  const auto thread_cap = limit_threads(args.threads);
  const int threads = int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  // Step 1: everything read and checked before any work or output.
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  MaterialSettings settings = args.settings;
  settings.light_map = args.light_map == "square" ? DirectionMap::HemiOctahedral
                                                  : DirectionMap::HemiOctahedralHorizon;
  if (args.seed >= 0) settings.seed = uint64_t(args.seed);
  try {
    check_material_settings(settings);
  } catch (const InputError& e) {
    std::string flag = e.field();
    std::replace(flag.begin(), flag.end(), '_', '-');
    throw InputError("--" + flag, e.message());
  }
  {
    // The folder is written beside its final name: the parent must be there.
    const std::filesystem::path final_dir(io::folder_siblings(args.out_dir).final_dir);
    const std::filesystem::path parent =
        final_dir.has_parent_path() ? final_dir.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    if (!std::filesystem::is_directory(parent, ec))
      throw InputError("-o", "the folder " + parent.string() + " does not exist", args.out_dir);
  }
  const nlohmann::json doc = io::parse_json_text(io::read_text_file(args.input, "a JSON file"), args.input);
  const bool is_scene = doc.is_object() && doc.contains("objects");
  std::shared_ptr<const VolumeTexture> owned_volume;  // a spec's
  const VolumeTexture* volume = nullptr;
  std::unique_ptr<FiberShader> shader;
  MaterialOptics optics;
  std::string cloth_name;
  std::unique_ptr<Scene> scene;
  std::unique_ptr<ClothScene> prepared;
  if (is_scene) {
    scene = std::make_unique<Scene>(io::load_scene(args.input, budget));
    int o = 0;
    if (!args.object.empty()) {
      o = -1;
      for (size_t i = 0; i < scene->objects.size(); ++i)
        if (scene->objects[i].name == args.object) o = int(i);
      if (o < 0) throw InputError("--object", "no object named '" + args.object + "'", args.input);
    }
    if (scene->objects.empty()) throw InputError("objects", "the scene has no cloth objects", args.input);
    try {
      prepared = std::make_unique<ClothScene>(*scene, budget);
    } catch (const InputError& e) {
      throw e.in_file(args.input);
    }
    optics = object_optics(*prepared, o);
    volume = &prepared->volume(o);
    cloth_name = scene->objects[size_t(o)].name;
    const RenderSettings& rs = scene->settings;
    shader = std::make_unique<FiberShader>(rs.fiber_model, scene->objects[o].cloth.shading.fiber_aspect,
                                           scene->objects[o].cloth.shading.exponent, rs.fiber_samples,
                                           hash_key(rs.seed, rng_stream::fiber_table, uint64_t(o)));
  } else {
    const ClothSpec spec = io::load_cloth_spec(args.input);
    try {
      owned_volume = std::make_shared<const VolumeTexture>(generate_volume(spec, budget));
      volume = owned_volume.get();
    } catch (const InputError& e) {
      throw e.in_file(args.input);
    }
    cloth_name = std::filesystem::path(args.input).stem().string();
    shader = std::make_unique<FiberShader>(optics.fiber_model, spec.shading.fiber_aspect,
                                           spec.shading.exponent, optics.fiber_samples,
                                           hash_key(optics.fiber_seed, rng_stream::fiber_table, 0));
  }
  if (args.depth_scale > 0.0f) optics.depth_scale = args.depth_scale;
  const uint64_t fixed = material_bake_fixed_bytes(*volume, settings, threads);
  if (fixed > budget)
    throw InputError("--memory", "the bake needs at least " + std::to_string(fixed >> 20) +
                                     " MiB (light fields and one view's table per thread), over "
                                     "the budget of " + std::to_string(budget >> 20) + " MiB");

  // Step 2: the bake.
  io::ProgressBar bar("material", args.quiet);
  MaterialBakeStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  const ClothMaterial material = bake_material(*volume, *shader, optics, settings, budget,
                                               [&](double f) { bar.update(f); }, &stats);
  bar.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Step 3: the folder, swapped in whole.
  io::MaterialInfo info;
  info.cloth_name = cloth_name;
  info.cloth_hash = hex16(volume->content_hash());
  info.source = std::filesystem::path(args.input).filename().string();
  info.stats = stats;
  io::write_material(args.out_dir, material, info);
  int max_rank = material.max_rank;
  double rank_sum = 0.0, worst = 0.0;
  for (int v = 0; v < material.view_count(); ++v) {
    rank_sum += material.rank[v];
    worst = std::max(worst, double(material.error[v]));
  }
  const double core_seconds = seconds * double(threads);
  const nlohmann::json report = {
      {"seconds", seconds},
      {"threads", threads},
      {"view_nodes", material.view_count()},
      {"light_nodes", material.light_count()},
      {"texels", settings.texels},
      {"rays", stats.rays},
      {"march_samples", stats.march_samples},
      {"fiber_evaluations", stats.fiber_evaluations},
      {"march_samples_per_core_second", double(stats.march_samples) / core_seconds},
      {"fiber_evaluations_per_core_second", double(stats.fiber_evaluations) / core_seconds},
      {"light_field_mib", double(stats.field_bytes) / double(1 << 20)},
      {"uncompressed_mib", stats.uncompressed_values * 2.0 / double(1 << 20)},
      {"max_rank", max_rank},
      {"mean_rank", rank_sum / double(material.view_count())},
      {"worst_view_error", worst},
      {"depth_scale", optics.depth_scale}};
  std::printf("%s\n", report.dump().c_str());
}
}  // namespace

void register_material_command(CLI::App& app, Action action) {
  auto args = std::make_shared<MaterialArgs>();
  CLI::App* cmd = app.add_subcommand(
      "material", "Bake a cloth material: one weave repeat for every view, light and distance");
  cmd->add_option("input", args->input, "cloth spec or scene JSON")->required();
  cmd->add_option("-o,--out", args->out_dir, "material folder to write")->required();
  cmd->add_option("--texels", args->settings.texels, "R: texels per repeat side, a power of 2")
      ->capture_default_str();
  cmd->add_option("--directions", args->settings.directions, "K: view nodes per side of each hemisphere")
      ->capture_default_str();
  cmd->add_option("--light-directions", args->settings.light_directions,
                  "KL: light nodes per side of each hemisphere")
      ->capture_default_str();
  cmd->add_option("--spp", args->settings.spp, "samples per texel and view node")
      ->capture_default_str();
  cmd->add_option("--max-error", args->settings.max_error,
                  "per view node: relative RMSE the factorisation may leave (0 = exact)")
      ->capture_default_str();
  cmd->add_option("--field-supersample", args->settings.field_supersample,
                  "light-field points per cell edge")
      ->capture_default_str();
  cmd->add_option("--light-map", args->light_map,
                  "light nodes: drawn toward the horizon, or the plain hemi-octahedral square")
      ->check(CLI::IsMember({"horizon", "square"}))
      ->capture_default_str();
  cmd->add_option("--fiber-tangent-nodes", args->settings.fiber_tangent_nodes,
                  "fibre response tabulated over N x N tangents per view node (0: exact per cell)")
      ->capture_default_str();
  cmd->add_option("--depth-scale", args->depth_scale,
                  "texture mm per world unit along the normal over along the surface "
                  "(default: the scene object's; 1 for a spec)");
  cmd->add_option("--object", args->object, "the scene object whose cloth to bake (default: the first)");
  cmd->add_option("--seed", args->seed, "seed of the texel samples")->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->callback([args, action] {
    if (action == Action::Run) run_material(*args);
  });
}

}  // namespace clothbake::cli
