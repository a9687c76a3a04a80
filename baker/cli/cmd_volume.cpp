// `clothbake volume SPEC_OR_SCENE.json -o DIR`: generate the volume texture
// (PAPER.md s.2), write DIR/volume.vdb, readable PNG previews and a summary.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/option_range.h"
#include "cli/commands.h"
#include "core/util/hex.h"
#include "cli/memory_budget.h"
#include "cli/thread_limit.h"
#include "core/util/error.h"
#include "core/texture/volume_generator.h"
#include "core/texture/crossings.h"
#include "core/texture/volume_preview.h"
#include "core/weave/drawdown_image.h"
#include "io/atomic_file.h"
#include "io/cloth_spec_json.h"
#include "io/image_io.h"
#include "io/system_info.h"
#include "io/vdb_writer.h"

namespace clothbake::cli {

namespace {

struct VolumeArgs {
  std::string input;
  std::string out_dir;
  int threads = 0;
  double memory_gib = 0.0;
};

std::string weave_label(const ClothSpec& spec) {
  if (!spec.draft_source.empty())
    return std::filesystem::path(spec.draft_source).filename().string();
  return spec.draft.empty() ? spec.pattern : "custom draft";
}

Image labelled(Image image, const std::string& text) {
  // A dark strip above the picture carries its caption.
  const int strip = 26;
  Image out(image.width, image.height + strip, 3);
  for (int y = 0; y < image.height; ++y)
    std::copy(image.at(0, y), image.at(0, y) + 3 * image.width, out.at(0, y + strip));
  io::draw_label(out, 6, 19, text, 15);
  return out;
}

// About 95 lines, kept whole: the command's three steps in order (read and
// check; generate; write the VDB, previews and report together), as each
// command reads.
void run_volume(const VolumeArgs& args) {
  const auto threads = limit_threads(args.threads);
  // Step 1: read and check everything before any output exists.
  const ClothSpec spec = io::load_cloth_spec(args.input);
  const uint64_t budget = memory_budget_bytes(args.memory_gib);
  // The command holds the grid and, while writing, its five OpenVDB grids:
  // measured peak 5.67 GB for a 91 x 480 overshot at the defaults (44.7 M
  // cells, grid 1.79 GB), so 90 bytes per cell on top of the grid's 40.
  const ResolutionSpec res = resolved_resolution(spec);
  const double cells = double(res.cells_x) * res.cells_y * res.layers;
  const double need = double(estimated_volume_bytes(spec)) + 90.0 * cells;
  if (need > double(budget))
    throw InputError("resolution",
                     std::to_string(res.cells_x) + " x " + std::to_string(res.cells_y) + " x " +
                         std::to_string(res.layers) + " cells need an estimated " +
                         std::to_string(uint64_t(need / (1024 * 1024))) +
                         " MiB with the VDB written, over the memory budget of " +
                         std::to_string(budget / (1024 * 1024)) + " MiB",
                     args.input);
  const auto t0 = std::chrono::steady_clock::now();
  const VolumeTexture volume = [&] {
    try {
      return generate_volume(spec, budget);
    } catch (const InputError& e) {
      throw e.in_file(args.input);
    }
  }();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Step 2: the previews and a summary for scripts and people.
  io::ensure_directory(args.out_dir);
  const std::filesystem::path dir(args.out_dir);
  const WeaveGeometry geom = weave_geometry(spec);
  const std::string desc = weave_label(spec) + ", " + std::to_string(volume.nx()) + " x " +
                           std::to_string(volume.ny()) + " x " + std::to_string(volume.nz()) +
                           " cells, seed " + std::to_string(spec.seed);
  const int repeats = 3, px_per_repeat = 256;
  const float ppm = 768.0f / std::max(geom.size_mm.x, geom.size_mm.y) / repeats;
  struct Preview {
    const char* file;
    Image image;
    bool linear;
  };
  const Preview previews[] = {
      {"top.png",
       labelled(preview_top(volume, repeats, px_per_repeat),
                "top view, " + std::to_string(repeats) + "x" + std::to_string(repeats) +
                    " repeats: " + desc),
       true},
      {"tangents.png",
       labelled(preview_tangents(volume, repeats, px_per_repeat),
                "fibre tangent of the top-most fibre cell, colour = 0.5 + 0.5 v"),
       false},
      {"section_warp.png",
       labelled(preview_section_along_warp(volume, 0.5f * spec.warp.spacing_mm, repeats, ppm),
                "section along warp end 0 (y across, z up), true aspect"),
       true},
      {"section_weft.png",
       labelled(preview_section_along_weft(volume, 0.5f * spec.weft.spacing_mm, repeats, ppm),
                "section along weft pick 0 (x across, z up), true aspect"),
       true}};

  double rho_sum = 0.0;
  size_t occupied = 0;
  for (const Cell& c : volume.cells()) {
    rho_sum += c.density;
    occupied += c.density > 0.0f;
  }
  nlohmann::json summary = {
      {"input", args.input},
      {"weave", weave_label(spec)},
      {"cells", {volume.nx(), volume.ny(), volume.nz()}},
      {"size_mm", {volume.size_mm().x, volume.size_mm().y, volume.size_mm().z}},
      {"mean_density", rho_sum / double(volume.cell_count())},
      {"occupied_fraction", double(occupied) / double(volume.cell_count())},
      {"seed", spec.seed},
      {"cells_hash", hex16(volume.content_hash())},
      {"generate_seconds", seconds},
      {"memory_bytes", uint64_t(need)},
      {"files",
       {"volume.vdb", "top.png", "tangents.png", "section_warp.png", "section_weft.png",
        "drawdown.png", "crossings.exr"}}};
  int ends = 0, picks = 0;
  repeat_threads(spec, ends, picks);
  summary["repeat_threads"] = {ends, picks};
  if (!spec.draft_source.empty()) summary["draft_source"] = spec.draft_source;
  // The drawdown beside the top view: the same way up (end 1 left, pick 1 at
  // the bottom), a few pixels per crossing however long the repeat.
  const int block = std::clamp(768 / std::max(ends, picks), 1, 32);
  const Image drawdown = drawdown_image(spec, block);
  const Image crossings = crossing_tops(volume, spec);

  // Step 3: every file written beside its final name, then all renamed into
  // place together: a failure or an interrupt leaves the folder as it was.
  std::vector<std::pair<std::string, std::function<void(const std::string&)>>> files;
  const std::string vdb_path = (dir / "volume.vdb").string();
  files.emplace_back(vdb_path, [&](const std::string& temp) {
    io::write_volume_vdb_to(temp, vdb_path, volume, desc);
  });
  for (const Preview& p : previews) {
    const std::string path = (dir / p.file).string();
    files.emplace_back(path, [&p, path](const std::string& temp) {
      io::write_png_to(temp, path, p.image, p.linear);
    });
  }
  const std::string drawdown_path = (dir / "drawdown.png").string();
  files.emplace_back(drawdown_path, [&](const std::string& temp) {
    io::write_png_to(temp, drawdown_path, drawdown, true);
  });
  const std::string crossings_path = (dir / "crossings.exr").string();
  files.emplace_back(crossings_path, [&](const std::string& temp) {
    io::write_exr_to(temp, crossings_path, crossings);
  });
  const std::string json_path = (dir / "volume.json").string();
  files.emplace_back(json_path, [&](const std::string& temp) {
    std::ofstream out(temp);
    out << summary.dump(2) << "\n";
    if (!out) throw InputError("", "cannot write summary", json_path);
  });
  io::write_all_atomically(files);
  std::printf("%s\n", summary.dump(2).c_str());
}

}  // namespace

void register_volume_command(CLI::App& app, Action action) {
  auto args = std::make_shared<VolumeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "volume", "Generate a cloth's volume texture: DIR/volume.vdb and PNG previews");
  cmd->add_option("input", args->input, "cloth spec or scene JSON, or a WIF draft")->required();
  cmd->add_option("-o,--out", args->out_dir, "output folder")->required();
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(in_range(0, 4096));
  add_memory_option(cmd, args->memory_gib);
  cmd->callback([args, action] {
    if (action == Action::Run) run_volume(*args);
  });
}

}  // namespace clothbake::cli
