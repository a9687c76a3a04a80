// `clothbake material SPEC_OR_SCENE.json -o DIR`: bake a cloth material, the
// appearance of one weave repeat for every view and light direction and every
// distance (docs/material-format.md), which lookup-render applies to any
// scene whose cloth matches.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>
#include <Eigen/Dense>
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
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

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
  bool estimate = false;  ///< time a probe of the work, print the estimate as JSON; write nothing
};

std::string hex16(uint64_t h) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)h);
  return hex;
}


double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// What `--estimate` measures and extrapolates (the bake's four steps,
/// material_bake.h). Only the bake's own seconds are estimated (what the
/// bake's report prints as "seconds"), not reading the input or writing the
/// folder.
struct MaterialEstimate {
  int view_nodes = 0, light_nodes = 0;
  uint64_t rays = 0;  ///< view marches of the whole bake: view nodes x texels^2 x spp
  int probe_light_nodes = 0, probe_view_nodes = 0;
  uint64_t probe_rays = 0;         ///< marched per light-field set (twice in all)
  double probe_seconds = 0.0;      ///< wall time of the whole probe
  double fields_seconds = 0.0;     ///< step 1, extrapolated
  double marches_seconds = 0.0;    ///< step 2 (fibre tables and marches), extrapolated
  double factorise_seconds = 0.0;  ///< step 3, extrapolated
  double mips_seconds = 0.0;       ///< step 4, extrapolated from a copy of the full-rank size
  double seconds = 0.0;
  uint64_t light_field_bytes = 0;  ///< the light fields
  uint64_t fixed_bytes = 0;        ///< fields plus one view's matrix per thread
  uint64_t max_bytes = 0;          ///< the table at full rank (every view at rank = light nodes)
};

/// Probe sizes: light nodes built and marched, view nodes marched, rays per
/// probe view. On the paper scene at the defaults (200 light nodes, 512 view
/// nodes) the probe takes about 2 s on 2 threads, mostly the 8 fields.
constexpr int k_probe_light_nodes = 8;
constexpr int k_probe_view_nodes = 32;
constexpr int k_probe_rays_per_view = 128;

/// `count` distinct node indices of [0, n) picked by the golden-ratio
/// sequence. Nodes cost differently by direction (horizon nodes march or
/// build longest), and node indices run row by row over a K x K grid: even
/// strides keep hitting the same column (with K = 16 and 8 picks of 512,
/// all on the horizon), the golden ratio mixes rows and columns.
std::vector<int> pick_nodes(int n, int count) {
  std::vector<int> out;
  std::vector<bool> taken(size_t(n), false);
  double x = 0.5;
  while (int(out.size()) < std::min(n, count)) {
    int i = std::min(n - 1, int(x * double(n)));
    while (taken[size_t(i)]) i = (i + 1) % n;
    taken[size_t(i)] = true;
    out.push_back(i);
    x += 0.6180339887498949;
    x -= std::floor(x);
  }
  return out;
}

/// Times a probe of the bake's real work on its threads, with the core's own
/// functions (LightFieldSet::build, FiberLightTable::build, material_sample,
/// march_view_ray_all_lights, an Eigen factorisation of the real size), and
/// extrapolates by counts:
///  - fields: P light nodes spread over the grid built, times L / P;
///  - marches: a march's cost is linear in the light nodes it serves (each
///    sample reads every node's transmittance and fibre response), so the
///    probe rays of each probe view are marched twice, with a 1-node and a
///    P-node field set, and the cost per ray is extrapolated to L nodes; the
///    fibre table (k^2 x L evaluations per view) is built for P nodes, times
///    L / P;
///  - factorisation: one Gram matrix and eigensolve of the real size, timed;
///  - mips: one level-0 table at full rank box-averaged, timed.
/// Each part's core-seconds are divided by the thread count, as the bake
/// runs its views in parallel. Writes nothing.
MaterialEstimate estimate_material(const VolumeTexture& volume, const FiberShader& shader,
                                   const MaterialOptics& optics, const MaterialSettings& settings,
                                   int threads) {
  using Clock = std::chrono::steady_clock;
  MaterialEstimate e;
  const auto probe_start = Clock::now();
  ClothMaterial material = material_layout(volume, optics, settings);
  const std::vector<Imath::V3f> light_local = material_light_directions(material);
  const int L = material.light_count(), V = material.view_count(), R = settings.texels;
  const uint64_t texels = uint64_t(R) * uint64_t(R);
  e.view_nodes = V;
  e.light_nodes = L;
  e.rays = uint64_t(V) * texels * uint64_t(settings.spp);
  e.light_field_bytes = LightFieldSet::bytes_for(volume, L, settings.field_supersample);
  e.fixed_bytes = material_bake_fixed_bytes(volume, settings, threads);
  {
    uint64_t floats = uint64_t(V) * uint64_t(L) * uint64_t(L);  // light factors
    for (int side = R;; side /= 2) {
      floats += uint64_t(V) * uint64_t(side) * uint64_t(side) * (uint64_t(L) * 3 + 1);
      if (side == 1) break;
    }
    e.max_bytes = floats * sizeof(float);
  }

  // Step 1: P light nodes' fields, spread over the grid; and the first of
  // them alone, for the marches' cost per light node.
  const int P = std::min(L, k_probe_light_nodes);
  e.probe_light_nodes = P;
  std::vector<Imath::V3f> probe_local, probe_texture;
  for (int n : pick_nodes(L, P)) {
    probe_local.push_back(light_local[size_t(n)]);
    probe_texture.push_back(material.texture_from_material(light_local[size_t(n)]));
  }
  auto t0 = Clock::now();
  const LightFieldSet fields_p = LightFieldSet::build(volume, probe_texture, optics.extinction_per_mm,
                                                      settings.field_supersample);
  e.fields_seconds = seconds_since(t0) * double(L) / double(P);
  const LightFieldSet fields_1 =
      LightFieldSet::build(volume, std::span(probe_texture).first(1), optics.extinction_per_mm,
                           settings.field_supersample);

  // Step 2: probe views spread over both hemispheres, on the bake's threads.
  const int VP = std::min(V, k_probe_view_nodes);
  e.probe_view_nodes = VP;
  const std::vector<int> views = pick_nodes(V, VP);
  const uint64_t rays_per_view = texels * uint64_t(settings.spp);
  const uint64_t probe_rays = std::min<uint64_t>(rays_per_view, k_probe_rays_per_view);
  e.probe_rays = probe_rays * uint64_t(VP);
  // Probe view i marches a run of consecutive rays (texels in the bake's
  // order, row by row, spp each) starting at a point of the repeat picked
  // per view: consecutive texels read neighbouring light-field points, and
  // the bake's speed depends on that (rays scattered over the repeat ran
  // 10 times slower per ray with the 200 nodes' fields).
  const auto first_ray = [&](int i) {
    const double x = double(i) * 0.6180339887498949 + 0.25;
    return uint64_t((x - std::floor(x)) * double(rays_per_view - probe_rays));
  };
  const bool tabulate = settings.fiber_tangent_nodes > 0 && optics.shading == ShadingMode::Fiber;
  struct Local {
    FiberLightTable table_1, table_p;
    NodeMarchScratch scratch_1, scratch_p;
    NodeMarchCounts counts;
    std::vector<Imath::V3f> radiance;
    double table_core = 0.0, march_1_core = 0.0, march_p_core = 0.0;
  };
  tbb::enumerable_thread_specific<Local> locals;
  tbb::parallel_for(0, VP, [&](int i) {
    Local& local = locals.local();
    const int view = views[size_t(i)];
    const Imath::V3f to_eye = material.view_grid.bake_direction(view);
    if (tabulate) {
      local.table_1.build(shader, std::span(probe_local).first(1), to_eye,
                          settings.fiber_tangent_nodes);
      const auto tt = Clock::now();
      local.table_p.build(shader, probe_local, to_eye, settings.fiber_tangent_nodes);
      local.table_core += seconds_since(tt);
    }
    // The probe rays, each marched for 1 and for P light nodes in turn (so
    // that a burst of other work on the machine slows both alike: their
    // difference is what is extrapolated).
    local.scratch_1.view_tag = local.scratch_p.view_tag = uint32_t(view) + 1;
    local.radiance.resize(size_t(P));
    const std::span<const Imath::V3f> lights_1 = std::span<const Imath::V3f>(probe_local).first(1);
    for (uint64_t r = first_ray(i); r < first_ray(i) + probe_rays; ++r) {
      const int k = int(r % uint64_t(settings.spp)), t = int(r / uint64_t(settings.spp));
      for (int pass = 0; pass < 2; ++pass) {
        const auto tm = Clock::now();
        NodeMarchInput in =
            material_sample(material, volume, shader, pass == 0 ? fields_1 : fields_p,
                            pass == 0 ? lights_1 : std::span<const Imath::V3f>(probe_local), view,
                            t % R, t / R, k);
        if (tabulate) in.fiber_table = pass == 0 ? &local.table_1 : &local.table_p;
        std::fill(local.radiance.begin(), local.radiance.end(), Imath::V3f(0.0f));
        if (in.length_mm > 0.0f)
          march_view_ray_all_lights(in, local.radiance.data(),
                                    pass == 0 ? local.scratch_1 : local.scratch_p, local.counts);
        (pass == 0 ? local.march_1_core : local.march_p_core) += seconds_since(tm);
      }
    }
  });
  double table_core = 0.0, march_1_core = 0.0, march_p_core = 0.0;
  for (const Local& l : locals) {
    table_core += l.table_core;
    march_1_core += l.march_1_core;
    march_p_core += l.march_p_core;
  }
  // Per ray at L nodes: linear through the 1-node and P-node costs.
  const double per_ray_1 = march_1_core / double(e.probe_rays);
  const double per_ray_p = march_p_core / double(e.probe_rays);
  const double per_ray =
      P > 1 ? per_ray_1 + std::max(0.0, per_ray_p - per_ray_1) * double(L - 1) / double(P - 1)
            : per_ray_p;
  const double per_view_table = table_core / double(VP) * double(L) / double(P);
  const double core_threads = double(std::max(threads, 1));
  e.marches_seconds =
      (per_view_table * double(V) + per_ray * double(e.rays)) / core_threads;

  // Step 3: one view's factorisation, at the real size (3 R^2 rows by L
  // light nodes) up to 64 x 64 texels, on a matrix of the same shape; the
  // products scale with the rows, the eigensolve does not. Every view's is
  // the same work.
  {
    const Eigen::Index rows = Eigen::Index(std::min<uint64_t>(texels, 64 * 64)) * 3;
    const double row_scale = double(texels) * 3.0 / double(rows);
    const Eigen::MatrixXf m = Eigen::MatrixXf::Random(rows, L).cwiseAbs();
    const auto tg = Clock::now();
    const Eigen::MatrixXd gram = (m.transpose() * m).cast<double>();
    const double gram_seconds = seconds_since(tg);
    const auto te = Clock::now();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
    const double eigen_seconds = seconds_since(te);
    const auto tu = Clock::now();
    const Eigen::MatrixXf u = m * eig.eigenvectors().cast<float>();
    const double product_seconds = seconds_since(tu);
    e.factorise_seconds = ((gram_seconds + product_seconds) * row_scale + eigen_seconds +
                           (u.size() > 0 ? 0.0 : 1.0)) *  // keeps u from being optimised away
                          double(V) / core_threads;
  }

  // Step 4: the mips (one thread in the bake): timed on 8 views of up to
  // 256 x 256 texels at rank min(L, 8), scaled by views, texels and rank to
  // the full-rank table (an upper bound).
  {
    ClothMaterial mips = material_layout(volume, optics, settings);
    mips.settings.texels = std::min(R, 256);
    mips.view_grid.k = 2;
    mips.max_rank = std::min(L, 8);
    mips.allocate();
    const auto tm = Clock::now();
    mips.build_mips();
    e.mips_seconds = seconds_since(tm) * double(V) / double(mips.view_count()) * double(texels) /
                     double(mips.settings.texels * mips.settings.texels) * double(L) /
                     double(mips.max_rank);
  }
  e.seconds = e.fields_seconds + e.marches_seconds + e.factorise_seconds + e.mips_seconds;
  e.probe_seconds = seconds_since(probe_start);
  return e;
}

void print_estimate(const MaterialSettings& settings, const MaterialEstimate& e, int threads) {
  const nlohmann::json report = {
      {"seconds", e.seconds},
      {"fields_seconds", e.fields_seconds},
      {"marches_seconds", e.marches_seconds},
      {"factorise_seconds", e.factorise_seconds},
      {"mips_seconds", e.mips_seconds},
      {"probe_seconds", e.probe_seconds},
      {"probe_light_nodes", e.probe_light_nodes},
      {"probe_view_nodes", e.probe_view_nodes},
      {"probe_rays", e.probe_rays},
      {"threads", threads},
      {"view_nodes", e.view_nodes},
      {"light_nodes", e.light_nodes},
      {"texels", settings.texels},
      {"spp", settings.spp},
      {"rays", e.rays},
      {"light_field_bytes", e.light_field_bytes},
      {"fixed_bytes", e.fixed_bytes},
      {"max_bytes", e.max_bytes}};
  std::printf("%s\n", report.dump(2).c_str());
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
      // A name, or failing that an index into the scene's objects.
      o = -1;
      for (size_t i = 0; i < scene->objects.size(); ++i)
        if (scene->objects[i].name == args.object) o = int(i);
      if (o < 0 && args.object.find_first_not_of("0123456789") == std::string::npos &&
          args.object.size() < 9 && std::stoi(args.object) < int(scene->objects.size()))
        o = std::stoi(args.object);
      if (o < 0)
        throw InputError("--object",
                         "no object named '" + args.object + "' (nor an index below " +
                             std::to_string(scene->objects.size()) + ")",
                         args.input);
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

  if (args.estimate) {
    print_estimate(settings, estimate_material(*volume, *shader, optics, settings, threads), threads);
    return;
  }
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
  cmd->add_option("--object", args->object, "the scene object whose cloth to bake, by name or index (default: the first)");
  cmd->add_option("--seed", args->seed, "seed of the texel samples")->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--estimate", args->estimate,
                "check the inputs, time a probe of the work, print the estimate as JSON; write "
                "nothing");
  cmd->callback([args, action] {
    if (action == Action::Run) run_material(*args);
  });
}

}  // namespace clothbake::cli
