// `clothbake bake SCENE.json -o BAKE_DIR`: view-dependent lookup EXRs per quad
// texel (core/baker.h, docs/lookup-format.md), full or adaptive to the camera.

#include <sys/statvfs.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/memory_budget.h"
#include "cli/thread_limit.h"
#include "core/baker.h"
#include "core/error.h"
#include "io/lookup_io.h"
#include "io/progress.h"
#include "io/scene_json.h"
#include "io/system_info.h"

namespace clothbake::cli {

namespace {

struct BakeArgs {
  std::string scene, out_dir, quads, map = "hemi-octahedral";
  BakeSettings settings;
  int threads = 0;
  double memory_gib = 0.0;
  bool quiet = false;
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
  args.settings.map =
      args.map == "hemi-octahedral" ? DirectionMap::HemiOctahedral : DirectionMap::Polar;
}

void run_bake_command(const BakeArgs& args) {
  const auto threads = limit_threads(args.threads);
  // Step 1: read and check everything, and refuse what cannot fit, before
  // any output exists.
  io::check_lookup_destination(args.out_dir);
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  const Scene scene = io::load_scene(args.scene);
  std::unique_ptr<Renderer> renderer;
  BakePlan plan;
  try {
    renderer = std::make_unique<Renderer>(scene, budget);
    plan = plan_bake(*renderer, args.settings);
  } catch (const InputError& e) {
    throw e.field().rfind("--", 0) == 0 ? e : e.in_file(args.scene);
  }
  const uint64_t bytes = io::lookup_bytes(plan.objects);
  if (bytes > budget)
    throw InputError("--texels", "the lookup would need " + mib(bytes) +
                                     " of memory, over the budget of " + mib(budget) +
                                     "; lower --texels or --directions, or use --adaptive");
  const std::filesystem::path out(args.out_dir);
  const std::filesystem::path parent = std::filesystem::absolute(out).parent_path();
  struct statvfs fs {};
  if (::statvfs(parent.c_str(), &fs) == 0) {
    const uint64_t free_bytes = uint64_t(fs.f_bavail) * fs.f_frsize;
    if (bytes > free_bytes)
      throw InputError("-o", "the lookup may need up to " + mib(bytes) + " on disk, only " +
                                 mib(free_bytes) + " free in " + parent.string());
  }

  if (!args.quiet)
    std::fprintf(stderr,
                 "bake: %s, K = %d, %llu direction tiles (full: %llu), %llu texels per direction "
                 "(full: %llu), %llu march samples, up to %s\n",
                 args.settings.adaptive ? "adaptive" : "full", args.settings.directions,
                 (unsigned long long)plan.baked_nodes, (unsigned long long)plan.full_nodes,
                 (unsigned long long)plan.texels, (unsigned long long)plan.full_texels,
                 (unsigned long long)plan.texel_direction_samples, mib(bytes).c_str());
  // Step 2: the bake.
  const auto t0 = std::chrono::steady_clock::now();
  io::ProgressBar bar("bake", args.quiet);
  const std::vector<LookupTable> tables =
      run_bake(*renderer, plan, args.settings, [&](double f) { bar.update(f); });
  bar.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Step 3: the folder, atomically, with what was saved against a full bake.
  io::LookupInfo info;
  info.scene_path = args.scene;
  info.scene_hash = io::scene_fingerprint(scene);
  for (int o = 0; o < renderer->object_count(); ++o) {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx",
                  (unsigned long long)renderer->volume(o).content_hash());
    info.cloth_hashes.push_back(hex);
    info.quad_counts.push_back(renderer->quad_count(o));
    info.meshes.push_back(summarize_mesh(scene.objects[size_t(o)].mesh));
  }
  info.settings = args.settings;
  const double work = double(std::max<uint64_t>(1, plan.texel_direction_samples));
  const double full_seconds = seconds * double(plan.full_texel_direction_samples) / work;
  // A full bake's files: every node of both sides at --texels for every quad.
  BakeSettings full = args.settings;
  full.adaptive = false;
  full.quad_begin = 0;
  full.quad_end = -1;
  const uint64_t full_bytes = io::lookup_bytes(plan_bake(*renderer, full).objects);
  info.statistics = {{"bake_seconds", seconds},
                     {"setup_seconds", renderer->stats().setup_seconds},
                     {"direction_tiles", plan.baked_nodes},
                     {"full_direction_tiles", plan.full_nodes},
                     {"texels", plan.texels},
                     {"full_texels", plan.full_texels},
                     {"march_samples", plan.texel_direction_samples},
                     {"full_march_samples", plan.full_texel_direction_samples},
                     {"bytes_uncompressed", bytes},
                     {"full_bytes_uncompressed", full_bytes},
                     {"full_seconds_estimated", full_seconds}};
  io::write_lookup(args.out_dir, tables, info, scene);
  uint64_t on_disk = 0;
  for (const auto& entry : std::filesystem::directory_iterator(args.out_dir))
    if (entry.is_regular_file()) on_disk += entry.file_size();
  nlohmann::json report = info.statistics;
  report["bytes_on_disk"] = on_disk;
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
                 full_seconds, mib(bytes).c_str(), mib(full_bytes).c_str());
}

}  // namespace

void register_bake_command(CLI::App& app, Action action) {
  auto args = std::make_shared<BakeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bake", "Bake view-dependent lookup EXRs per quad texel (docs/lookup-format.md)");
  cmd->add_option("scene", args->scene, "scene JSON")->required();
  cmd->add_option("-o,--out", args->out_dir, "output folder (replaced atomically)")->required();
  cmd->add_flag("--adaptive", args->settings.adaptive,
                "derive quads, texels and directions from the scene's camera");
  cmd->add_option("--directions", args->settings.directions,
                  "K: direction nodes per side of each hemisphere")
      ->check(CLI::Range(2, 64));
  cmd->add_option("--texels", args->settings.texels, "R: texels per quad side (full bake)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--spp", args->settings.spp, "jittered sub-texel samples per texel")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--texels-per-pixel", args->settings.texels_per_pixel,
                  "adaptive: texels per projected pixel")
      ->check(CLI::Range(0.01, 64.0));
  cmd->add_option("--direction-map", args->map,
                  "layout of the direction nodes (docs/lookup-format.md)")
      ->check(CLI::IsMember({"polar", "hemi-octahedral"}));
  cmd->add_option("--quads", args->quads, "bake quads A-B only (inclusive), for merge");
  cmd->add_option("--seed", args->settings.seed, "seed of the sub-texel jitter");
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->callback([args, action] {
    BakeArgs checked = *args;
    finish_bake_args(checked);
    if (action == Action::Run) run_bake_command(checked);
  });
}

}  // namespace clothbake::cli
