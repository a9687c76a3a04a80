// `clothbake merge PART_DIR... -o OUT_DIR`: joins partial bakes of one scene
// (`clothbake bake --quads A-B` or `--shard I/N`) into one lookup folder,
// identical to a whole bake of the union (docs/formats/lookup.md), or the
// parts of a sharded material bake (`clothbake material --shard I/N`) into
// the material an unsharded bake writes, byte for byte (docs/guide/farm.md).

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/util/error.h"
#include "io/folder_output.h"
#include "io/lookup_io.h"
#include "io/material_io.h"
#include "io/material_merge.h"

namespace clothbake::cli {

namespace {
struct MergeArgs {
  std::vector<std::string> parts;
  std::string out_dir;
};

void run_material_merge(const MergeArgs& a) {
  io::check_folder_parent(a.out_dir, "-o");
  io::check_folder_destination(a.out_dir, "material");
  for (const std::string& dir : a.parts)
    if (!io::is_material_folder(dir))
      throw InputError("parts", dir + " is not a material folder, but " + a.parts.front() +
                                    " is: merge joins parts of one kind");
  io::MaterialInfo info;
  const ClothMaterial material = io::merge_material_parts(a.parts, info);
  io::write_material(a.out_dir, material, info);
  const nlohmann::json report = {{"out", a.out_dir},
                                 {"parts", a.parts},
                                 {"views", material.view_count()},
                                 {"max_rank", material.max_rank},
                                 {"bytes_uncompressed", io::material_uncompressed_bytes(material)}};
  std::printf("%s\n", report.dump(2).c_str());
}

void run_merge(const MergeArgs& a) {
  if (io::is_material_folder(a.parts.front())) return run_material_merge(a);
  io::check_lookup_destination(a.out_dir);
  io::LookupInfo info;
  const std::vector<LookupTable> tables = io::merge_lookups(a.parts, info);
  // The lights and object names the parts recorded (the scene file is not needed).
  const Scene scene = io::read_lookup_scene(a.parts.front());
  io::write_lookup(a.out_dir, tables, info, scene);
  uint64_t baked = 0, total = 0;
  for (const LookupTable& t : tables)
    for (int q = 0; q < t.quad_count(); ++q) {
      total += t.sizes[q] > 0;
      baked += t.quad_baked(q);
    }
  const nlohmann::json report = {{"out", a.out_dir},
                                 {"parts", a.parts},
                                 {"scene_hash", info.scene_hash},
                                 {"quads_baked", baked},
                                 {"quads_in_layout", total},
                                 {"bytes_uncompressed", io::lookup_bytes(tables)}};
  std::printf("%s\n", report.dump(2).c_str());
}
}  // namespace

void register_merge_command(CLI::App& app, Action action) {
  auto args = std::make_shared<MergeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "merge", "Join partial bakes (bake --quads/--shard) of one scene into one lookup folder, "
               "or the parts of a sharded material bake (material --shard) into the material");
  cmd->add_option("parts", args->parts, "lookup or material folders of the parts")->required();
  cmd->add_option("-o,--out", args->out_dir, "output folder (replaced atomically)")->required();
  cmd->callback([args, action] {
    if (action == Action::Run) run_merge(*args);
  });
}

}  // namespace clothbake::cli
