// `clothbake material SPEC_OR_SCENE.json -o DIR`: bake a cloth material, the
// appearance of one weave repeat for every view and light direction and every
// distance (docs/formats/material.md), which lookup-render applies to any
// scene whose cloth matches. Read and check, call the core, write.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/material_options.h"
#include "cli/memory_budget.h"
#include "cli/option_range.h"
#include "cli/setting_flags.h"
#include "cli/shard_option.h"
#include "cli/thread_limit.h"
#include "core/material_bake/bake_rules.h"
#include "core/material_bake/material_bake.h"
#include "core/material_bake/material_probe.h"
#include "core/material_bake/material_source.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"
#include "io/folder_output.h"
#include "io/material_input.h"
#include "io/material_io.h"
#include "io/material_report.h"
#include "io/progress.h"
#include "io/system_info.h"

namespace clothbake::cli {

namespace {
struct MaterialArgs {
  std::string input, out_dir, object;
  MaterialSettings settings;
  MaterialChoiceOptions choice;  ///< --address and whether --texels was given
  float depth_scale = 0.0f;      // 0: the scene object's, or 1 for a spec
  int threads = 0;
  double memory_gib = 0.0;
  long long seed = -1;
  bool quiet = false;
  bool estimate = false;  ///< time a probe of the work, print the estimate as JSON; write nothing
  std::string parts = "auto";  ///< auto: colour-free parts where possible
  std::string shard;           ///< "I/N": part I of N (material_shard.h), for merge
};

/// The input read, with the depth scale asked.
io::MaterialInput read_input(const MaterialArgs& args, uint64_t budget) {
  const io::PartsRequest parts = args.parts == "rgb"                  ? io::PartsRequest::Rgb
                                 : args.parts == "specular-warp-weft" ? io::PartsRequest::ColourFree
                                                                      : io::PartsRequest::Auto;
  io::MaterialInput in;
  try {
    in = io::read_material_input(args.input, args.object, parts, budget);
  } catch (const InputError& e) {
    throw with_flag(k_material_flags, e);
  }
  if (args.depth_scale > 0.0f) in.source.optics.depth_scale = args.depth_scale;
  return in;
}

/// Said before the work, not refused (bake_rules.h, TexelAdvice): only a
/// whole repeat the user asked for can leave too few texels a thread. The
/// advice is more texels where they fit the budget, else per crossing.
void warn_texels(const TexelAdvice& a, const MaterialSettings& s, const io::MaterialInput& in,
                 int threads, uint64_t budget) {
  if (!a.too_few()) return;
  MaterialSettings more = s;
  more.texels = a.advised_texels;
  const uint64_t bytes =
      material_bake_fixed_bytes(unbaked_material(in.source, more), *in.source.volume, threads);
  char advice[256];
  if (bytes <= budget)
    std::snprintf(advice, sizeof advice, "--texels %d gives %.1f (the bake holds about %llu MiB)",
                  a.advised_texels, double(a.advised_texels) / a.threads_across,
                  (unsigned long long)(bytes >> 20));
  else if (in.source.parts == MaterialParts::SpecularWarpWeft)
    std::snprintf(advice, sizeof advice,
                  "more texels would not fit --memory-gib; leave --address out, or give "
                  "--address crossings, to address the texels per crossing");
  else
    std::snprintf(advice, sizeof advice, "more texels would not fit --memory-gib");
  std::fprintf(stderr,
               "clothbake: warning: --texels %d spans %d x %d threads per repeat: %.2f texels "
               "per thread, too few to resolve the weave (at least 2; the paper cloth has "
               "16). %s.\n",
               s.texels, in.ends, in.picks, a.texels_per_thread, advice);
}

/// What following a refusal's advice would take here, probed as --estimate
/// probes a bake: ", about 120 MB on disk, about 5 min here (estimated)".
std::string advised_cost(const MaterialSource& src, const MemoryAdvice& advice, int threads) {
  const MaterialEstimate e = probe_material(src, advice.settings, threads);
  const std::string time = e.seconds < 90.0
                               ? std::to_string(std::max(1, int(std::lround(e.seconds)))) + " s"
                               : std::to_string(int(std::lround(e.seconds / 60.0))) + " min";
  const uint64_t mb = std::max<uint64_t>(1, (e.disk_bytes + 500000) / 1000000);
  return ", about " + std::to_string(mb) + " MB on disk, about " + time + " here (estimated)";
}

/// What the report and --estimate add (the add-on shows it as the warning).
void add_texels(const TexelAdvice& a, nlohmann::json& j) {
  if (!a.known()) return;
  j["texels_per_thread"] = a.texels_per_thread;
  if (a.too_few()) j["texels_advised"] = a.advised_texels;
}

void run_material(const MaterialArgs& args) {
  const auto thread_cap = limit_threads(args.threads);
  const int threads =
      int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  // Step 1: everything read and checked before any work or output.
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  MaterialSettings settings = args.settings;
  if (args.seed >= 0) settings.seed = uint64_t(args.seed);
  const ShardOption shard_option = parse_shard(args.shard, "--shard");
  const MaterialShard shard{shard_option.index, shard_option.count};
  io::check_folder_parent(args.out_dir, "-o");
  io::check_folder_destination(args.out_dir, "material");
  const io::MaterialInput in = read_input(args, budget);
  // What the bake may hold: the budget less the program and its input as
  // read (a large draft's volumes can be most of it: 16 GB for a 641 x 641
  // one at the default resolution).
  const uint64_t held = io::resident_bytes();
  const uint64_t bake_budget = budget > held ? budget - held : 0;
  const MaterialSource& src = in.source;
  settings.parts = src.parts;
  BakeRequest request = bake_request(args.choice, settings);
  // A part of a sharded bake: per crossing is baked whole, so auto is the repeat.
  if (!shard.whole() && !request.address) request.address = MaterialAddress::Repeat;
  BakePlan plan;
  try {
    // The settings as given first (ranges, parts, shard), then as chosen.
    MaterialSettings asked = settings;
    asked.address = request.address.value_or(MaterialAddress::Repeat);
    check_material_bake(src, asked, shard);
    plan = plan_material_bake(src, settings, request, in.ends, in.picks, threads, bake_budget);
    settings = plan.settings;
    check_material_bake(src, settings, shard);
    if (request.address)
      warn_texels(texel_advice(settings, in.ends, in.picks), settings, in, threads, bake_budget);
    if (!plan.fits) {
      const MemoryAdvice advice = advice_for_memory(src, plan, threads, bake_budget);
      throw InputError(
          "memory",
          plan.mode + " holds " + std::to_string(plan.fixed_bytes >> 20) +
              " MiB before its table grows (light fields and view tables), "
              "over the " +
              std::to_string(bake_budget >> 20) + " MiB the budget of " +
              std::to_string(budget >> 20) +
              " MiB leaves beside the program and its input as read (" +
              std::to_string(held >> 20) + " MiB; " + plan.reason + "). " +
              (advice.text.empty() ? "Lower --light-directions or raise --memory-gib"
                                   : "Fits: " + advice.text + advised_cost(src, advice, threads)));
    }
  } catch (const InputError& e) {
    throw with_flag(k_material_flags, e);
  }
  const TexelAdvice advice = texel_advice(settings, in.ends, in.picks);
  if (args.estimate) {
    nlohmann::json j = io::material_estimate_json(
        settings, probe_material(src, settings, threads, shard), threads);
    j["plan"] = plan.why;
    // The program and its input as read (before the probe, whose memory the
    // bake does not keep), plus the bake's own high point.
    j["resident_bytes"] = held;
    j["peak_bytes"] = held + j["bake_peak_bytes"].get<uint64_t>();
    add_texels(advice, j);
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }

  // Step 2: the bake.
  io::ProgressBar bar("material", args.quiet);
  MaterialBakeStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  const ClothMaterial material = bake_material(
      src, settings, bake_budget, [&](double f) { bar.update(f); }, &stats, shard);
  bar.finish();
  const double seconds = seconds_since(t0);

  // Step 3: the folder, swapped in whole.
  io::MaterialInfo info;
  info.cloth_name = in.cloth_name;
  info.source = std::filesystem::path(args.input).filename().string();
  info.stats = stats;
  io::write_material(args.out_dir, material, info);
  nlohmann::json report = io::material_bake_report_json(material, stats, seconds, threads);
  report["plan"] = plan.why;
  report["peak_resident_bytes"] = io::peak_resident_bytes();
  report["bytes_on_disk"] = io::folder_bytes(args.out_dir);
  add_texels(advice, report);
  std::printf("%s\n", report.dump().c_str());
}
}  // namespace

void register_material_command(CLI::App& app, Action action) {
  auto args = std::make_shared<MaterialArgs>();
  MaterialSettings& s = args->settings;
  CLI::App* cmd = app.add_subcommand(
      "material", "Bake a cloth material: one weave repeat for every view, light and distance");
  cmd->add_option("input", args->input, "cloth spec or scene JSON")->required();
  cmd->add_option("-o,--out", args->out_dir, "material folder to write")->required();
  add_material_setting_options(cmd, s, args->choice);
  cmd->add_option("--depth-scale", args->depth_scale,
                  "texture mm per world unit along the normal over along the surface "
                  "(default: the scene object's; 1 for a spec)");
  cmd->add_option("--object", args->object,
                  "the scene object whose cloth to bake, by name or index (default: the first)");
  cmd->add_option("--seed", args->seed, "seed of the texel samples")->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(in_range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_option("--parts", args->parts,
                  "what the table stores: colour-free parts that take the yarn colours when "
                  "the material renders (specular-warp-weft), RGB with the colours baked in, or "
                  "auto: colour-free where possible (fibre shading, a cloth made from a spec)")
      ->check(CLI::IsMember({"auto", "rgb", "specular-warp-weft"}))
      ->capture_default_str();
  cmd->add_option("--shard", args->shard,
                  "I/N: bake part I (from 1) of N, a share of the view nodes, for "
                  "'clothbake merge' (docs/guide/farm.md)");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--estimate", args->estimate,
                "check the inputs, time a probe of the work, print the estimate as JSON; write "
                "nothing");
  cmd->callback([args, action] {
    if (action == Action::Run) run_material(*args);
  });
}

}  // namespace clothbake::cli
