// `clothbake bake SCENE.json -o BAKE_DIR`: view-dependent lookup EXRs per quad
// texel (core/baker.h, docs/formats/lookup.md), full or adaptive to the camera.
// `--estimate` stops after step 1 with the plan and a timed estimate.

#include <sys/statvfs.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/option_range.h"
#include "cli/commands.h"
#include "cli/memory_budget.h"
#include "cli/setting_flags.h"
#include "cli/shard_option.h"
#include "cli/thread_limit.h"
#include "core/bake/baker.h"
#include "core/util/error.h"
#include "core/util/hex.h"
#include "io/folder_output.h"
#include "io/lookup_io.h"
#include "io/progress.h"
#include "io/scene_json.h"
#include "io/system_info.h"

namespace clothbake::cli {

namespace {

struct BakeArgs {
  std::string scene, out_dir, quads, shard, map = "hemi-octahedral";
  BakeSettings settings;
  int threads = 0;
  double memory_gib = 0.0;
  bool quiet = false;
  bool estimate = false;  ///< print the plan and a timed estimate instead of baking
};

void parse_quads(const std::string& text, BakeSettings& s) {
  if (text.empty()) return;
  int a = -1, b = -1;
  char dash = 0;
  std::istringstream in(text);
  if (!(in >> a >> dash >> b) || dash != '-' || a < 0 || b < a || !in.eof())
    throw InputError("--quads",
                     "expected A-B with 0 <= A <= B (quads A to B inclusive), got '" + text + "'");
  s.quad_begin = a;
  s.quad_end = b + 1;
}

std::string mib(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1 << 20));
  return buf;
}

/// The settings from the values CLI11 leaves as text.
void finish_bake_args(BakeArgs& args) {
  parse_quads(args.quads, args.settings);
  const ShardOption shard = parse_shard(args.shard, "--shard");
  args.settings.shard_index = shard.index;
  args.settings.shard_count = shard.count;
  args.settings.map =
      args.map == "hemi-octahedral" ? DirectionMap::HemiOctahedral : DirectionMap::Polar;
}

/// The flags of the bake settings the core names in an error (BakeSettings'
/// fields).
constexpr SettingFlag k_bake_flags[] = {{"directions", "--directions"},
                                        {"texels", "--texels"},
                                        {"spp", "--spp"},
                                        {"texels_per_pixel", "--texels-per-pixel"},
                                        {"quads", "--quads"},
                                        {"shard", "--shard"}};

/// What step 1 leaves for the bake: the scene, prepared, and the plan,
/// all checked.
struct BakeJob {
  Scene scene;
  std::unique_ptr<ClothScene> prepared;  ///< refers to `scene`
  BakePlan plan;
  uint64_t bytes = 0;  ///< the lookup, uncompressed
};

/// Step 1: read and check everything, and refuse what cannot fit, before
/// any output exists.
void prepare_bake(const BakeArgs& args, BakeJob& job) {
  io::check_lookup_destination(args.out_dir);
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  job.scene = io::load_scene(args.scene, budget);
  try {
    job.prepared = std::make_unique<ClothScene>(job.scene, budget);
    job.plan = plan_bake(*job.prepared, args.settings);
  } catch (const InputError& e) {
    // The core names a bake setting; here it is the flag that set it.
    if (flag_of(k_bake_flags, e.field())) throw with_flag(k_bake_flags, e);
    throw e.in_file(args.scene);
  }
  job.bytes = io::lookup_bytes(job.plan.objects);
  if (job.bytes > budget)
    throw InputError("--texels", "the lookup would need " + mib(job.bytes) +
                                     " of memory, over the budget of " + mib(budget) +
                                     "; lower --texels or --directions, or use --adaptive");
  const std::filesystem::path out(args.out_dir);
  const std::filesystem::path parent = std::filesystem::absolute(out).parent_path();
  struct statvfs fs {};
  if (::statvfs(parent.c_str(), &fs) == 0) {
    const uint64_t free_bytes = uint64_t(fs.f_bavail) * fs.f_frsize;
    if (job.bytes > free_bytes)
      throw InputError("-o", "the lookup may need up to " + mib(job.bytes) + " on disk, only " +
                                 mib(free_bytes) + " free in " + parent.string());
  }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// March samples the probe evaluates: 0.3 to 0.5 s on the paper scene with 2
/// idle threads. Long enough that a burst of other work on the machine does
/// not dominate its timing (8192 samples, 0.1 s, were off by up to 60% on a
/// shared machine) and that every (quad, node) pair of a full K = 8 bake is
/// drawn about 4 times.
constexpr uint64_t k_probe_samples = 32768;

struct BakeEstimate {
  uint64_t probe_samples = 0;
  double probe_seconds = 0.0;
  double cache_seconds = 0.0;  ///< light caches (Cached transmittance): paid once, not per sample
  double seconds = 0.0;        ///< the bake's seconds (run_bake), extrapolated
};

/// Times a probe of the real bake work (core probe_bake) and extrapolates to
/// the whole plan. The light caches are built first and timed apart: run_bake
/// builds them once, whatever the number of samples.
BakeEstimate estimate_bake(BakeJob& job, const BakeSettings& settings) {
  BakeEstimate e;
  ClothScene& prepared = *job.prepared;
  const double setup_before = prepared.setup_seconds();
  prepared.prepare_light_caches();
  e.cache_seconds = prepared.setup_seconds() - setup_before;
  const auto t0 = std::chrono::steady_clock::now();
  e.probe_samples = probe_bake(prepared, job.plan, settings, k_probe_samples);
  e.probe_seconds = seconds_since(t0);
  e.seconds = e.cache_seconds;
  if (e.probe_samples > 0)
    e.seconds +=
        e.probe_seconds * double(job.plan.texel_direction_samples) / double(e.probe_samples);
  return e;
}

/// `--estimate`: the plan and the estimate as one JSON object on stdout.
void print_estimate(const BakeArgs& args, const BakeJob& job, const BakeEstimate& e) {
  const nlohmann::json report = {
      {"march_samples", job.plan.texel_direction_samples},
      {"full_march_samples", job.plan.full_texel_direction_samples},
      {"direction_tiles", job.plan.baked_nodes},
      {"texels", job.plan.texels},
      {"bytes_uncompressed", job.bytes},
      {"seconds_estimated", e.seconds},
      {"probe_samples", e.probe_samples},
      {"probe_seconds", e.probe_seconds},
      {"setup_seconds", job.prepared->setup_seconds()},
      {"threads", tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)},
      {"adaptive", args.settings.adaptive}};
  std::printf("%s\n", report.dump(2).c_str());
}

/// Step 3: the folder, atomically, with what was saved against a full bake.
void write_bake(const BakeArgs& args, const BakeJob& job, const std::vector<LookupTable>& tables,
                double seconds) {
  const ClothScene& prepared = *job.prepared;
  const BakePlan& plan = job.plan;
  io::LookupInfo info;
  info.scene_path = args.scene;
  info.scene_hash = io::scene_fingerprint(job.scene);
  for (int o = 0; o < prepared.object_count(); ++o) {
    info.cloth_hashes.push_back(hex16(prepared.volume(o).content_hash()));
    info.quad_counts.push_back(prepared.quad_count(o));
    info.meshes.push_back(summarize_mesh(job.scene.objects[size_t(o)].mesh));
  }
  info.settings = args.settings;
  const double work = double(std::max<uint64_t>(1, plan.texel_direction_samples));
  const double full_seconds = seconds * double(plan.full_texel_direction_samples) / work;
  // A full bake's files: every node of both sides at --texels for every quad.
  BakeSettings full = args.settings;
  full.adaptive = false;
  full.quad_begin = 0;
  full.quad_end = -1;
  const uint64_t full_bytes = io::lookup_bytes(plan_bake(prepared, full).objects);
  info.statistics = {{"bake_seconds", seconds},
                     {"setup_seconds", prepared.setup_seconds()},
                     {"direction_tiles", plan.baked_nodes},
                     {"full_direction_tiles", plan.full_nodes},
                     {"texels", plan.texels},
                     {"full_texels", plan.full_texels},
                     {"march_samples", plan.texel_direction_samples},
                     {"full_march_samples", plan.full_texel_direction_samples},
                     {"bytes_uncompressed", job.bytes},
                     {"full_bytes_uncompressed", full_bytes},
                     {"full_seconds_estimated", full_seconds}};
  io::write_lookup(args.out_dir, tables, info, job.scene);
  nlohmann::json report = info.statistics;
  report["bytes_on_disk"] = io::folder_bytes(args.out_dir);
  report["out"] = args.out_dir;
  std::printf("%s\n", report.dump(2).c_str());
  if (args.settings.adaptive && !args.quiet)
    std::fprintf(stderr,
                 "adaptive bake saved against a full bake at K = %d, R = %d: direction tiles %llu "
                 "of %llu, texels %llu of %llu, %.1f s of an estimated %.1f s, %s of %s "
                 "(uncompressed)\n",
                 args.settings.directions, args.settings.texels,
                 (unsigned long long)plan.baked_nodes, (unsigned long long)plan.full_nodes,
                 (unsigned long long)plan.texels, (unsigned long long)plan.full_texels, seconds,
                 full_seconds, mib(job.bytes).c_str(), mib(full_bytes).c_str());
}

/// A normal bake runs the probe for its "about N s" only when the probe is
/// at most 1% of the bake's samples: small bakes would pay for it visibly.
constexpr uint64_t k_probe_share = 100;

void run_bake_command(const BakeArgs& args) {
  const auto threads = limit_threads(args.threads);
  BakeJob job;
  prepare_bake(args, job);
  const BakePlan& plan = job.plan;
  if (args.estimate) {
    print_estimate(args, job, estimate_bake(job, args.settings));
    return;
  }
  BakeEstimate estimate;
  std::string about;
  if (!args.quiet && plan.texel_direction_samples >= k_probe_share * k_probe_samples) {
    estimate = estimate_bake(job, args.settings);
    about = ", about " + std::to_string(std::llround(estimate.seconds)) + " s";
  }
  if (!args.quiet)
    std::fprintf(stderr,
                 "bake: %s, K = %d, %llu direction tiles (full: %llu), %llu texels per direction "
                 "(full: %llu), %llu march samples, up to %s%s\n",
                 args.settings.adaptive ? "adaptive" : "full", args.settings.directions,
                 (unsigned long long)plan.baked_nodes, (unsigned long long)plan.full_nodes,
                 (unsigned long long)plan.texels, (unsigned long long)plan.full_texels,
                 (unsigned long long)plan.texel_direction_samples, mib(job.bytes).c_str(),
                 about.c_str());
  // Step 2: the bake. Its seconds include the light caches, even when the
  // estimate built them.
  const auto t0 = std::chrono::steady_clock::now();
  io::ProgressBar bar("bake", args.quiet);
  const std::vector<LookupTable> tables =
      run_bake(*job.prepared, plan, args.settings, [&](double f) { bar.update(f); });
  bar.finish();
  write_bake(args, job, tables, estimate.cache_seconds + seconds_since(t0));
}

}  // namespace

void register_bake_command(CLI::App& app, Action action) {
  auto args = std::make_shared<BakeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bake", "Bake view-dependent lookup EXRs per quad texel (docs/formats/lookup.md)");
  cmd->add_option("scene", args->scene, "scene JSON")->required();
  cmd->add_option("-o,--out", args->out_dir, "output folder (replaced atomically)")->required();
  cmd->add_flag("--adaptive", args->settings.adaptive,
                "derive quads, texels and directions from the scene's camera");
  cmd->add_option("--directions", args->settings.directions,
                  "K: direction nodes per side of each hemisphere")
      ->check(in_range(k_min_directions, k_max_directions));
  cmd->add_option("--texels", args->settings.texels, "R: texels per quad side (full bake)")
      ->check(in_range(k_min_texels, k_max_texels));
  cmd->add_option("--spp", args->settings.spp, "jittered sub-texel samples per texel")
      ->check(in_range(k_min_bake_spp, k_max_bake_spp));
  cmd->add_option("--texels-per-pixel", args->settings.texels_per_pixel,
                  "adaptive: texels per projected pixel")
      ->check(in_range(0.01, double(k_max_texels_per_pixel)));
  cmd->add_option("--direction-map", args->map,
                  "layout of the direction nodes (docs/formats/lookup.md)")
      ->check(CLI::IsMember({"polar", "hemi-octahedral"}));
  cmd->add_option("--quads", args->quads, "bake quads A-B only (inclusive), for merge");
  cmd->add_option("--shard", args->shard,
                  "I/N: bake part I (from 1) of N, every N-th quad, for merge (docs/guide/farm.md)");
  cmd->add_option("--seed", args->settings.seed, "seed of the sub-texel jitter");
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(in_range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--estimate", args->estimate,
                "plan, check and time a probe of the work, print the estimate as JSON; bake "
                "nothing");
  cmd->callback([args, action] {
    BakeArgs checked = *args;
    finish_bake_args(checked);
    if (action == Action::Run) run_bake_command(checked);
  });
}

}  // namespace clothbake::cli
