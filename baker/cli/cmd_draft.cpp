// `clothbake draft INPUT -o DIR`: the cloth's draft without generating a
// volume, in a moment: DIR/drawdown.png for a person (and the Blender panel)
// and DIR/draft.json, every thread's state and colour, for tools that
// recolour a draft (the add-on's palette) or check a reading of it.

#include <algorithm>
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
#include "core/util/error.h"
#include "core/weave/crossing_neighbourhoods.h"
#include "core/weave/drawdown_image.h"
#include "core/weave/thread_layout.h"
#include "core/weave/weave.h"
#include "io/atomic_file.h"
#include "io/cloth_spec_json.h"
#include "io/image_io.h"

namespace clothbake::cli {

namespace {

struct DraftArgs {
  std::string input;
  std::string out_dir;
  int block = 0;
};

nlohmann::json rgb(const Imath::V3f& c) { return {c.x, c.y, c.z}; }

void run_draft(const DraftArgs& args) {
  const ClothSpec spec = io::load_cloth_spec(args.input);
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout ends = thread_layout(spec, draft, true);
  const ThreadLayout picks = thread_layout(spec, draft, false);
  const int block = args.block > 0 ? args.block
                                   : std::clamp(768 / std::max(ends.count(), picks.count()), 1, 32);
  const Image image = drawdown_image(spec, block);

  nlohmann::json up = nlohmann::json::array();
  for (int p = 0; p < picks.count(); ++p) {
    std::vector<int> row(ends.count());
    for (int e = 0; e < ends.count(); ++e) row[e] = draft.warp_up(p, e) ? 1 : 0;
    up.push_back(row);
  }
  // The distinct colours in order of first use (warp, then weft): what an
  // artist recolours, one entry changing every thread of that colour.
  std::vector<Imath::V3f> palette;
  auto index_of = [&](const Imath::V3f& c) {
    for (size_t i = 0; i < palette.size(); ++i)
      if (palette[i] == c) return int(i);
    palette.push_back(c);
    return int(palette.size()) - 1;
  };
  auto family = [&](const ThreadLayout& layout, const YarnSpec& yarn, nlohmann::json& colors,
                    nlohmann::json& index, nlohmann::json& spacing, nlohmann::json& width) {
    colors = nlohmann::json::array();
    index = nlohmann::json::array();
    spacing = nlohmann::json::array();
    width = nlohmann::json::array();
    for (int i = 0; i < layout.count(); ++i) {
      colors.push_back(rgb(layout.color(i)));
      index.push_back(index_of(layout.color(i)));
      spacing.push_back(yarn.spacings_mm.empty() ? yarn.spacing_mm
                                                 : yarn.spacings_mm[i % yarn.spacings_mm.size()]);
      width.push_back(layout.width_mm(i));
    }
  };
  nlohmann::json j = {{"source", args.input},
                      {"source_program", spec.draft_program},
                      {"wif", spec.draft_source},
                      {"ends", ends.count()},
                      {"picks", picks.count()},
                      {"warp_up", up},
                      {"drawdown_block_px", block}};
  family(ends, spec.warp, j["warp_colors"], j["warp_color_index"], j["warp_spacing_mm"],
         j["warp_width_mm"]);
  family(picks, spec.weft, j["weft_colors"], j["weft_color_index"], j["weft_spacing_mm"],
         j["weft_width_mm"]);
  // How many different places the weave holds (docs/design/material.md, "The
  // weave's variety"): colours not counted.
  const NeighbourhoodCounts hood = crossing_neighbourhoods(spec);
  j["neighbourhoods"] = {{"weave_repeat", {hood.ends, hood.picks}},
                         {"crossings", hood.crossings()},
                         {"plus_1", hood.plus1},
                         {"square_1", hood.square[0]},
                         {"square_2", hood.square[1]},
                         {"square_3", hood.square[2]}};
  nlohmann::json pal = nlohmann::json::array();
  for (const Imath::V3f& c : palette) pal.push_back(rgb(c));
  j["palette"] = pal;

  io::ensure_directory(args.out_dir);
  const std::filesystem::path dir(args.out_dir);
  const std::string png_path = (dir / "drawdown.png").string();
  const std::string json_path = (dir / "draft.json").string();
  std::vector<std::pair<std::string, std::function<void(const std::string&)>>> files;
  files.emplace_back(png_path, [&](const std::string& temp) {
    io::write_png_to(temp, png_path, image, true);
  });
  files.emplace_back(json_path, [&](const std::string& temp) {
    std::ofstream out(temp);
    out << j.dump() << "\n";
    if (!out) throw InputError("", "cannot write the draft", json_path);
  });
  io::write_all_atomically(files);
  std::printf("draft: %d ends x %d picks, %zu colours; weave repeat %d x %d, %d distinct "
              "crossings (plus-1 neighbourhoods) -> %s\n",
              ends.count(), picks.count(), palette.size(), hood.ends, hood.picks, hood.plus1,
              args.out_dir.c_str());
}

}  // namespace

void register_draft_command(CLI::App& app, Action action) {
  auto args = std::make_shared<DraftArgs>();
  CLI::App* cmd = app.add_subcommand(
      "draft", "A cloth's draft without its volume: DIR/drawdown.png and DIR/draft.json");
  cmd->add_option("input", args->input, "a WIF draft, a cloth spec or a scene JSON")->required();
  cmd->add_option("-o,--out", args->out_dir, "output folder")->required();
  cmd->add_option("--block", args->block,
                  "pixels per crossing in drawdown.png (0 = fit the repeat in about 768)")
      ->check(in_range(0, 64));
  cmd->callback([args, action] {
    if (action == Action::Run) run_draft(*args);
  });
}

}  // namespace clothbake::cli
