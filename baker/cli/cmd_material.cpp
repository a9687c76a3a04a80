// `clothbake material SPEC_OR_SCENE.json -o DIR`: bake a cloth material, the
// appearance of one weave repeat for every view and light direction and every
// distance (docs/material-format.md), which lookup-render applies to any
// scene whose cloth matches. Read and check, call the core, write.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "cli/commands.h"
#include "cli/memory_budget.h"
#include "cli/shard_option.h"
#include "cli/thread_limit.h"
#include "core/material/material_bake.h"
#include "core/material/material_probe.h"
#include "core/material/material_shard.h"
#include "core/material/material_source.h"
#include "core/scene/scene_checks.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"
#include "core/weave/thread_layout.h"
#include "io/cloth_spec_json.h"
#include "io/enum_names.h"
#include "io/folder_output.h"
#include "io/json_reader.h"
#include "io/material_io.h"
#include "io/material_report.h"
#include "io/progress.h"
#include "io/scene_json.h"
#include "io/text_file.h"

namespace clothbake::cli {

namespace {
/// An option whose value is one of an enum's spellings (io/enum_names.h),
/// checked by CLI11 and shown with its default's spelling.
template <typename E, std::size_t N>
CLI::Option* add_enum_option(CLI::App* cmd, const std::string& flag, E& value,
                             const io::EnumNames<E, N>& names, const std::string& help) {
  std::map<std::string, E> map;
  for (const auto& [name, v] : names) map[name] = v;
  return cmd->add_option(flag, value, help)
      ->transform(CLI::CheckedTransformer(map))
      ->default_str(io::enum_name(names, value));
}
}  // namespace

namespace {
struct MaterialArgs {
  std::string input, out_dir, object;
  MaterialSettings settings;
  float depth_scale = 0.0f;  // 0: the scene object's, or 1 for a spec
  int threads = 0;
  double memory_gib = 0.0;
  long long seed = -1;
  bool quiet = false;
  bool estimate = false;  ///< time a probe of the work, print the estimate as JSON; write nothing
  std::string parts = "auto";  ///< auto: colour-free parts where possible
  std::string shard;           ///< "I/N": part I of N (material_shard.h), for merge
};

/// The input read: a scene's object (the scene kept alive for its volume),
/// or a cloth spec.
struct MaterialInput {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<ClothScene> prepared;
  MaterialSource source;
  std::string cloth_name;
  /// Warp ends and weft picks over the material's repeat (0: a VDB volume,
  /// whose threads are not known).
  int ends = 0, picks = 0;
};

/// The threads over the repeat of `spec` (its colour-free cut when the
/// parts are colour-free: what the material's texels cover).
void count_threads(const ClothSpec& spec, MaterialInput& in) {
  const WeaveDraft draft = draft_of(spec);
  in.ends = thread_layout(spec, draft, true).count();
  in.picks = thread_layout(spec, draft, false).count();
}

MaterialInput read_input(const MaterialArgs& args, uint64_t budget) {
  MaterialInput in;
  const MaterialParts parts =
      args.parts == "rgb" ? MaterialParts::Rgb : MaterialParts::SpecularWarpWeft;
  const nlohmann::json doc =
      io::parse_json_text(io::read_text_file(args.input, "a JSON file"), args.input);
  try {
    if (doc.is_object() && doc.contains("objects")) {
      in.scene = std::make_unique<Scene>(io::load_scene(args.input, budget));
      const Scene& scene = *in.scene;
      if (scene.objects.empty()) throw InputError("objects", "the scene has no cloth objects");
      const int o = args.object.empty() ? 0 : find_object(scene, args.object);
      if (o < 0)
        throw InputError("--object", "no object named '" + args.object + "' (nor an index below " +
                                         std::to_string(scene.objects.size()) + ")");
      in.prepared = std::make_unique<ClothScene>(*in.scene, budget);
      in.source = material_source(*in.prepared, o, parts, budget);
      in.cloth_name = in.scene->objects[size_t(o)].name;
      if (in.source.parts == MaterialParts::SpecularWarpWeft)
        count_threads(in.source.cloth, in);
      else if (!scene.objects[size_t(o)].volume)
        count_threads(scene.objects[size_t(o)].cloth, in);
      if (args.parts == "specular-warp-weft" && in.source.parts != parts)
        throw InputError("--parts", "colour-free parts are not possible for this object: " +
                                        colour_parts_refusal(scene.settings.shading,
                                                             scene.objects[size_t(o)].volume !=
                                                                 nullptr));
    } else {
      const ClothSpec spec = io::load_cloth_spec(args.input);
      in.source = material_source(spec, parts, budget);
      in.cloth_name = std::filesystem::path(args.input).stem().string();
      count_threads(parts == MaterialParts::SpecularWarpWeft ? in.source.cloth : spec, in);
    }
  } catch (const InputError& e) {
    throw e.in_file(args.input);
  }
  if (args.depth_scale > 0.0f) in.source.optics.depth_scale = args.depth_scale;
  return in;
}

void run_material(const MaterialArgs& args) {
  const auto thread_cap = limit_threads(args.threads);
  const int threads =
      int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  // Step 1: everything read and checked before any work or output.
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  MaterialSettings settings = args.settings;
  if (args.seed >= 0) settings.seed = uint64_t(args.seed);
  check_material_settings(settings);  // CLI11 checked each; this is the core's word
  const ShardOption shard_option = parse_shard(args.shard, "--shard");
  const MaterialShard shard{shard_option.index, shard_option.count};
  try {
    check_material_shard(shard, MaterialLayout::of(settings).view_count());
  } catch (const InputError& e) {
    throw InputError("--shard", e.message() + " (--directions " +
                                    std::to_string(settings.directions) + ")");
  }
  io::check_folder_parent(args.out_dir, "-o");
  io::check_folder_destination(args.out_dir, "material");
  const MaterialInput in = read_input(args, budget);
  const MaterialSource& src = in.source;
  settings.parts = src.parts;
  if (settings.address == MaterialAddress::Crossings && src.parts != MaterialParts::SpecularWarpWeft)
    throw InputError("--address", "crossings needs colour-free parts (its blocks and colours come "
                                  "from the cloth's threads); this bake stores " +
                                  std::string(args.parts == "rgb" ? "RGB (--parts rgb)"
                                                                  : "RGB: fibre shading and a cloth "
                                                                    "made from a spec are needed"));
  if (settings.address == MaterialAddress::Crossings && !shard.whole())
    throw InputError("--shard", "a material addressed per crossing is baked whole");
  // R texels span the whole repeat: a draft of many threads leaves few per
  // thread, and below 2 the over-and-under of neighbouring threads falls
  // inside one texel. Said before the work, not refused: the bake is still
  // the box average of the cloth.
  // Addressed per crossing, R texels span one thread whatever the repeat.
  const int threads_across =
      settings.address == MaterialAddress::Crossings ? 1 : std::max(in.ends, in.picks);
  const double texels_per_thread = threads_across > 0 ? double(settings.texels) / threads_across : 0.0;
  int texels = settings.texels;  // the advice: the smallest R that gives 4
  while (threads_across > 0 && texels < k_max_material_texels &&
         double(texels) / threads_across < 4.0)
    texels *= 2;
  // What the report and --estimate add (the add-on shows it as the warning).
  auto add_texels = [&](nlohmann::json& j) {
    if (threads_across == 0) return;
    j["texels_per_thread"] = texels_per_thread;
    if (texels_per_thread < 2.0) j["texels_advised"] = texels;
  };
  if (threads_across > 0 && texels_per_thread < 2.0) {
    std::fprintf(stderr,
                 "clothbake: warning: --texels %d spans %d x %d threads per repeat: %.2f texels "
                 "per thread, too few to resolve the weave (at least 2; the paper cloth has "
                 "16). --texels %d gives %.1f (see --estimate for its cost).\n",
                 settings.texels, in.ends, in.picks, texels_per_thread, texels,
                 double(texels) / threads_across);
  }
  ClothMaterial shape = unbaked_material(*src.volume, src.optics, settings);
  if (shape.colour_parts()) shape.set_cloth(src.cloth, src.palette);
  const uint64_t fixed = material_bake_fixed_bytes(shape, *src.volume, threads);
  if (fixed > budget)
    throw InputError("--memory", "the bake needs at least " + std::to_string(fixed >> 20) +
                                     " MiB (light fields and one view's table per thread), over "
                                     "the budget of " + std::to_string(budget >> 20) + " MiB");
  if (args.estimate) {
    const MaterialEstimate e =
        probe_material(*src.volume, *src.shader, src.optics, settings, threads,
                       src.parts == MaterialParts::SpecularWarpWeft ? &src.cloth : nullptr,
                       shard);
    nlohmann::json j = io::material_estimate_json(settings, e, threads);
    add_texels(j);
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }

  // Step 2: the bake.
  io::ProgressBar bar("material", args.quiet);
  MaterialBakeStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  ClothMaterial material = bake_material(*src.volume, *src.shader, src.optics, settings, budget,
                                         [&](double f) { bar.update(f); }, &stats,
                                         src.parts == MaterialParts::SpecularWarpWeft ? &src.cloth
                                                                                      : nullptr,
                                         shard);
  if (material.colour_parts()) {
    material.set_cloth(src.cloth, src.palette);
    material.written_repeats = src.written_repeats;
  }
  bar.finish();
  const double seconds = seconds_since(t0);

  // Step 3: the folder, swapped in whole.
  io::MaterialInfo info;
  info.cloth_name = in.cloth_name;
  info.source = std::filesystem::path(args.input).filename().string();
  info.stats = stats;
  io::write_material(args.out_dir, material, info);
  nlohmann::json report = io::material_bake_report_json(material, stats, seconds, threads);
  add_texels(report);
  std::printf("%s\n", report.dump().c_str());
}
}  // namespace

void register_material_command(CLI::App& app, Action action) {
  auto args = std::make_shared<MaterialArgs>();
  MaterialSettings& s = args->settings;
  // The checks of material_settings.h that a range cannot state.
  const CLI::Validator power_of_two(
      [](std::string& v) {
        const int n = std::atoi(v.c_str());
        return n > 0 && (n & (n - 1)) == 0
                   ? std::string()
                   : "must be a power of 2 (the mip levels halve it down to 1), got " + v;
      },
      "POWER OF 2");
  const CLI::Validator tangent_nodes(
      [](std::string& v) {
        const int n = std::atoi(v.c_str());
        return n == 0 || (n >= k_min_fiber_tangent_nodes && n <= k_max_fiber_tangent_nodes)
                   ? std::string()
                   : "must be 0 or in [" + std::to_string(k_min_fiber_tangent_nodes) + ", " +
                         std::to_string(k_max_fiber_tangent_nodes) + "], got " + v;
      },
      "0 OR RANGE");
  CLI::App* cmd = app.add_subcommand(
      "material", "Bake a cloth material: one weave repeat for every view, light and distance");
  cmd->add_option("input", args->input, "cloth spec or scene JSON")->required();
  cmd->add_option("-o,--out", args->out_dir, "material folder to write")->required();
  cmd->add_option("--texels", s.texels, "R: texels per repeat side, a power of 2")
      ->check(CLI::Range(k_min_material_texels, k_max_material_texels) & power_of_two)
      ->capture_default_str();
  cmd->add_option("--directions", s.directions, "K: view nodes per side of each hemisphere")
      ->check(CLI::Range(k_min_material_directions, k_max_material_directions))
      ->capture_default_str();
  cmd->add_option("--light-directions", s.light_directions,
                  "KL: light nodes per side of each hemisphere")
      ->check(CLI::Range(k_min_material_directions, k_max_material_directions))
      ->capture_default_str();
  cmd->add_option("--spp", s.spp, "samples per texel and view node")
      ->check(CLI::Range(k_min_material_spp, k_max_material_spp))->capture_default_str();
  cmd->add_option("--max-error", s.max_error,
                  "per view node: relative RMSE the factorisation may leave (0 = exact)")
      ->check(CLI::Range(k_min_material_error, k_max_material_error))->capture_default_str();
  cmd->add_option("--field-supersample", s.field_supersample, "light-field points per cell edge")
      ->check(CLI::Range(k_min_field_supersample, k_max_field_supersample))
      ->capture_default_str();
  add_enum_option(cmd, "--light-map", s.light_map, io::k_light_map_flags,
                  "light nodes: drawn toward the horizon, or the plain hemi-octahedral square");
  add_enum_option(cmd, "--light-fields", s.light_fields, io::k_light_field_names,
                  "how the bake reads light toward each sample: interpolated between the "
                  "cells' centres, or marched through the sample's own layer (right where "
                  "cells are opaque, about 6 x the march's time); auto: layer-march when "
                  "sigma x the densest cell's rho x a field cell's edge exceeds 1");
  cmd->add_flag("--view-parallax,!--no-view-parallax", s.view_parallax,
               "read each view node where its ray meets the eye's at a depth fitted to the "
               "material (sharper weave between view nodes of a thick cloth)")
      ->capture_default_str();
  add_enum_option(cmd, "--address", s.address, io::k_material_address_names,
                  "what the texels cover: the whole repeat (--texels per repeat side), or one "
                  "block per distinct crossing neighbourhood, addressed per crossing (--texels "
                  "per crossing side): its size follows the weave's variety, not its repeat");
  cmd->add_option("--context", s.context,
                  "--address crossings: crossings either side of a block's that its light "
                  "fields span")
      ->check(CLI::Range(k_min_material_context, k_max_material_context))
      ->capture_default_str();
  add_enum_option(cmd, "--stencil", s.stencil, io::k_crossing_stencil_names,
                  "--address crossings: what makes two crossings one block: their plus-1 "
                  "stencil, or their 3 x 3 window (about 3 x the blocks; the neighbouring "
                  "threads' crossings, which grazing rays see)");
  cmd->add_option("--members", s.members,
                  "--address crossings: crossings of each class a block averages, spread over "
                  "the class (1: its first crossing alone; more average the crossings' own "
                  "randomness, at that many times the bake)")
      ->check(CLI::Range(k_min_material_members, k_max_material_members))
      ->capture_default_str();
  cmd->add_option("--phase-bins", s.phase_bins,
                  "--address crossings: bins of the ply phase of the yarn on top at a "
                  "crossing, each its own block (about that many times the blocks): the "
                  "generator's per-yarn random phase, which shows per pixel at a thread per "
                  "pixel or two; 1: not in the classes")
      ->check(CLI::Range(k_min_phase_bins, k_max_phase_bins))
      ->capture_default_str();
  cmd->add_option("--fiber-tangent-nodes", s.fiber_tangent_nodes,
                  "fibre response tabulated over N x N tangents per view node (0: exact per cell)")
      ->check(tangent_nodes)->capture_default_str();
  cmd->add_option("--depth-scale", args->depth_scale,
                  "texture mm per world unit along the normal over along the surface "
                  "(default: the scene object's; 1 for a spec)");
  cmd->add_option("--object", args->object,
                  "the scene object whose cloth to bake, by name or index (default: the first)");
  cmd->add_option("--seed", args->seed, "seed of the texel samples")->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_option("--parts", args->parts,
                  "what the table stores: colour-free parts that take the yarn colours when "
                  "the material renders (specular-warp-weft), RGB with the colours baked in, or "
                  "auto: colour-free where possible (fibre shading, a cloth made from a spec)")
      ->check(CLI::IsMember({"auto", "rgb", "specular-warp-weft"}))
      ->capture_default_str();
  cmd->add_option("--shard", args->shard,
                  "I/N: bake part I (from 1) of N, a share of the view nodes, for "
                  "'clothbake merge' (docs/farm.md)");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--estimate", args->estimate,
                "check the inputs, time a probe of the work, print the estimate as JSON; write "
                "nothing");
  cmd->callback([args, action] {
    if (action == Action::Run) run_material(*args);
  });
}

}  // namespace clothbake::cli
