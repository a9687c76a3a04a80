#include "io/material_io.h"

#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include "core/material/material_bake.h"
#include "core/util/error.h"
#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/lookup_manifest.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace {
namespace fs = std::filesystem;
namespace oiio = OIIO;
using Imath::V3f;
using nlohmann::json;

constexpr const char* k_manifest = "manifest.json";
constexpr const char* k_light_file = "light_factors.exr";

std::string level_file(int m) { return "level_" + std::to_string(m) + ".exr"; }

const char* shading_name(ShadingMode s) { return s == ShadingMode::Isotropic ? "isotropic" : "fiber"; }
const char* fiber_model_name(FiberModelKind k) {
  switch (k) {
    case FiberModelKind::Table: return "table";
    case FiberModelKind::KajiyaKay: return "kajiya-kay";
    default: return "ellipsoid";
  }
}

/// "k0003": zero-padded, so that the names sort in component order (OpenEXR
/// stores channels sorted by name; readers find them by name).
std::string component_name(int k) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "k%04d", k);
  return buf;
}

/// The pixel of texel (x, y) of view node v in a level's atlas (tiles of
/// side x side, K to a row; docs/material-format.md, "The images").
size_t atlas_pixel(int v, int x, int y, int side, int K) {
  const size_t px = size_t(v % K) * side + x, py = size_t(v / K) * side + y;
  return py * size_t(K) * side + px;
}

/// The coefficient channels' names: alpha, then R, G, B of each component.
std::vector<std::string> level_channels(int max_rank) {
  std::vector<std::string> names{"A"};
  for (int k = 0; k < max_rank; ++k)
    for (const char* c : {"R", "G", "B"}) names.push_back(component_name(k) + "." + c);
  return names;
}

void write_image(const std::string& path, int width, int height,
                 const std::vector<std::string>& channels, oiio::TypeDesc type, const void* data) {
  oiio::ImageSpec spec(width, height, int(channels.size()), type);
  spec.channelnames = channels;
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");  // no capture date: the same material gives the same bytes
  auto out = oiio::ImageOutput::create(path);
  if (!out) throw InputError("", oiio::geterror(), path);
  if (!out->open(path, spec) || !out->write_image(type, data) || !out->close()) {
    const std::string why = out->geterror();
    throw InputError("", why.empty() ? "write error" : why, path);
  }
}

/// Reads an image of exactly width x height x channels (names checked).
template <typename T>
std::vector<T> read_image(const std::string& path, int width, int height,
                          const std::vector<std::string>& channels, oiio::TypeDesc type) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError("", "missing: the material folder is incomplete", path);
  auto in = oiio::ImageInput::open(path);
  if (!in) throw InputError("", "cannot read: " + oiio::geterror(), path);
  const oiio::ImageSpec& spec = in->spec();
  if (spec.width != width || spec.height != height || spec.depth != 1)
    throw InputError("", "is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                             " pixels; the manifest says " + std::to_string(width) + " x " +
                             std::to_string(height),
                     path);
  if (spec.nchannels != int(channels.size()))
    throw InputError("", "has " + std::to_string(spec.nchannels) + " channels; the manifest's " +
                             "max_rank gives " + std::to_string(channels.size()),
                     path);
  // Channels by name: the file may store them in any order.
  std::vector<int> from(channels.size(), -1);
  for (size_t c = 0; c < channels.size(); ++c) {
    for (int f = 0; f < spec.nchannels; ++f)
      if (spec.channelnames[f] == channels[c]) from[c] = f;
    if (from[c] < 0) throw InputError("", "has no channel \"" + channels[c] + "\"", path);
  }
  std::vector<T> file(size_t(width) * size_t(height) * channels.size());
  if (!in->read_image(0, 0, 0, spec.nchannels, type, file.data())) {
    std::string why = in->geterror();
    throw InputError("", "cannot read: " + (why.empty() ? std::string("corrupt or truncated") : why),
                     path);
  }
  std::vector<T> data(file.size());
  const size_t nc = channels.size();
  for (size_t p = 0; p < size_t(width) * size_t(height); ++p)
    for (size_t c = 0; c < nc; ++c) data[p * nc + c] = file[p * nc + size_t(from[c])];
  for (const T& x : data)
    if (!std::isfinite(float(x))) throw InputError("", "holds a value that is not finite", path);
  return data;
}

json manifest_json(const ClothMaterial& m, const MaterialInfo& info) {
  const MaterialSettings& s = m.settings;
  const MaterialOptics& o = m.optics;
  json j;
  j["format"] = k_material_format_name;
  j["version"] = k_material_format_version;
  j["cloth"] = {{"name", info.cloth_name}, {"hash", info.cloth_hash}, {"source", info.source}};
  j["repeat_mm"] = {m.repeat_mm.x, m.repeat_mm.y, m.repeat_mm.z};
  j["texels"] = s.texels;
  j["levels"] = m.levels();
  j["directions"] = s.directions;
  j["light_directions"] = s.light_directions;
  j["direction_map"] = "hemi-octahedral";
  j["light_direction_map"] =
      s.light_map == DirectionMap::HemiOctahedralHorizon ? "hemi-octahedral-horizon" : "hemi-octahedral";
  j["spp"] = s.spp;
  j["max_error"] = s.max_error;
  j["field_supersample"] = s.field_supersample;
  j["fiber_tangent_nodes"] = s.fiber_tangent_nodes;
  j["seed"] = s.seed;
  j["optics"] = {{"depth_scale", o.depth_scale},
                 {"extinction_per_mm", o.extinction_per_mm},
                 {"shading", shading_name(o.shading)},
                 {"isotropic_albedo", {o.isotropic_albedo.x, o.isotropic_albedo.y,
                                       o.isotropic_albedo.z}},
                 {"fiber_model", fiber_model_name(o.fiber_model)},
                 {"fiber_samples", o.fiber_samples},
                 {"fiber_seed", o.fiber_seed},
                 {"step_cells", o.step_cells},
                 {"cutoff", o.cutoff},
                 {"light_roulette", o.light_roulette}};
  j["max_rank"] = m.max_rank;
  json ranks = json::array(), errors = json::array();
  for (int v = 0; v < m.view_count(); ++v) {
    ranks.push_back(m.rank[v]);
    errors.push_back(m.error[v]);
  }
  j["ranks"] = ranks;
  j["errors"] = errors;
  json levels = json::array();
  for (int l = 0; l < m.levels(); ++l) levels.push_back(level_file(l));
  j["files"] = {{"levels", levels}, {"light_factors", k_light_file}};
  j["bake"] = {{"rays", info.stats.rays},
               {"march_samples", info.stats.march_samples},
               {"fiber_evaluations", info.stats.fiber_evaluations}};
  return j;
}
}  // namespace

uint64_t material_uncompressed_bytes(const ClothMaterial& m) {
  uint64_t bytes = uint64_t(m.view_count()) * m.light_count() * std::max(1, m.max_rank) * 4;
  for (int l = 0; l < m.levels(); ++l)
    bytes += uint64_t(m.view_count()) * m.level_side(l) * m.level_side(l) *
             (1 + 3 * uint64_t(m.max_rank)) * 2;
  return bytes;
}

bool is_material_folder(const std::string& dir) {
  std::error_code ec;
  const fs::path p = fs::path(dir) / k_manifest;
  if (!fs::is_regular_file(p, ec)) return false;
  try {
    const json j = parse_json_text(read_text_file(p.string(), "a JSON file"), p.string());
    return j.is_object() && j.contains("format") && j["format"] == k_material_format_name;
  } catch (const InputError&) {
    return false;
  }
}

// About 60 lines: the atlas layout written out, then the swap.
void write_material(const std::string& dir, const ClothMaterial& m, const MaterialInfo& info) {
  const FolderSiblings names = folder_siblings(dir);
  const fs::path temp_dir(names.temp_dir);
  std::error_code ec;
  {
    const fs::path final_dir(names.final_dir);
    if (fs::exists(final_dir, ec)) {
      if (!fs::is_directory(final_dir, ec)) throw InputError("", "exists and is not a folder", dir);
      if (!fs::is_empty(final_dir, ec) && !fs::exists(final_dir / k_manifest, ec))
        throw InputError("", "exists and is not a material folder (no manifest.json); not "
                             "replacing it", dir);
    }
  }
  // A disk too small for the images is refused before anything is written.
  const fs::path parent = fs::absolute(fs::path(names.final_dir)).parent_path();
  const fs::space_info space = fs::space(parent, ec);
  const uint64_t need = material_uncompressed_bytes(m);
  if (!ec && space.available < need)
    throw InputError("", "needs up to " + std::to_string(need >> 20) + " MiB and the disk has " +
                             std::to_string(space.available >> 20) + " MiB free",
                     dir);
  fs::remove_all(temp_dir, ec);
  UnfinishedOutput unfinished(temp_dir.string());
  fs::create_directories(temp_dir, ec);
  if (ec)
    throw InputError("", "cannot create the temporary folder " + temp_dir.string() + ": " +
                             ec.message(),
                     dir);
  try {
    const int K = m.settings.directions;
    const std::vector<std::string> channels = level_channels(m.max_rank);
    const size_t nc = channels.size();
    for (int l = 0; l < m.levels(); ++l) {
      const int side = m.level_side(l);
      const int width = K * side, height = 2 * K * side;
      std::vector<Imath::half> pixels(size_t(width) * height * nc);
      const size_t texels = size_t(side) * side;
      for (int v = 0; v < m.view_count(); ++v)
        for (int y = 0; y < side; ++y)
          for (int x = 0; x < side; ++x) {
            const size_t t = size_t(y) * side + x;
            Imath::half* out = &pixels[atlas_pixel(v, x, y, side, K) * nc];
            out[0] = m.alpha[l][size_t(v) * texels + t];
            const V3f* c = &m.coefficients[l][(size_t(v) * texels + t) * m.max_rank];
            for (int k = 0; k < m.max_rank; ++k)
              out[1 + 3 * k] = c[k].x, out[2 + 3 * k] = c[k].y, out[3 + 3 * k] = c[k].z;
          }
      write_image((temp_dir / level_file(l)).string(), width, height, channels,
                  oiio::TypeDesc::HALF, pixels.data());
    }
    std::vector<std::string> light_channels;
    for (int k = 0; k < std::max(1, m.max_rank); ++k) light_channels.push_back(component_name(k));
    std::vector<float> lights(size_t(m.light_count()) * m.view_count() * light_channels.size(), 0.0f);
    for (int v = 0; v < m.view_count(); ++v)
      for (int n = 0; n < m.light_count(); ++n)
        for (int k = 0; k < m.max_rank; ++k)
          lights[(size_t(v) * m.light_count() + n) * light_channels.size() + k] =
              m.light_factors[(size_t(v) * m.light_count() + n) * m.max_rank + k];
    write_image((temp_dir / k_light_file).string(), m.light_count(), m.view_count(),
                light_channels, oiio::TypeDesc::FLOAT, lights.data());
    errno = 0;
    std::ofstream f(temp_dir / k_manifest, std::ios::binary);
    f << manifest_json(m, info).dump(2) << "\n";
    f.close();
    if (!f) throw InputError("", errno != 0 ? std::strerror(errno) : "write error", k_manifest);
  } catch (const InputError& e) {
    throw InputError("", "cannot write " + fs::path(e.file()).filename().string() + ": " +
                             e.message() + "; nothing under this name was changed",
                     dir);
  }
  publish_folder(unfinished, names, "material");
}

// About 90 lines: every manifest field checked before any image is read.
ClothMaterial read_material(const std::string& dir, MaterialInfo& info,
                            uint64_t memory_budget) {
  const std::string manifest_path = (fs::path(dir) / k_manifest).string();
  const json doc = parse_json_text(read_text_file(manifest_path, "a JSON file"), manifest_path);
  const JsonObject top(doc, "", manifest_path);
  auto need = [&](const char* key) {
    if (!top.has(key)) top.fail(key, "is missing");
  };
  for (const char* key : {"format", "version", "cloth", "repeat_mm", "texels", "levels",
                          "directions", "light_directions", "spp", "max_error", "seed", "optics",
                          "max_rank", "ranks", "errors", "files"})
    need(key);
  std::string format;
  top.read("format", format);
  if (format != k_material_format_name)
    top.fail("format", "expected \"" + std::string(k_material_format_name) + "\", got \"" +
                           format + "\"");
  int version = 0;
  top.read("version", version);
  if (version != k_material_format_version)
    top.fail("version", "this material has format version " + std::to_string(version) +
                            "; this clothbake reads version " +
                            std::to_string(k_material_format_version));
  ClothMaterial m;
  MaterialSettings& s = m.settings;
  top.read("texels", s.texels);
  top.read("directions", s.directions);
  top.read("light_directions", s.light_directions);
  top.read("spp", s.spp);
  top.read("max_error", s.max_error);
  top.read("seed", s.seed);
  top.read("field_supersample", s.field_supersample);
  std::string light_map = "hemi-octahedral";
  top.read("light_direction_map", light_map);
  if (light_map == "hemi-octahedral-horizon") s.light_map = DirectionMap::HemiOctahedralHorizon;
  else if (light_map == "hemi-octahedral") s.light_map = DirectionMap::HemiOctahedral;
  else top.fail("light_direction_map", "must be \"hemi-octahedral-horizon\" or \"hemi-octahedral\"");
  top.read("fiber_tangent_nodes", s.fiber_tangent_nodes);
  try {
    check_material_settings(s);
  } catch (const InputError& e) {
    throw InputError(e.field(), e.message(), manifest_path);
  }
  top.read("repeat_mm", m.repeat_mm);
  if (!(m.repeat_mm.x > 0 && m.repeat_mm.y > 0 && m.repeat_mm.z > 0))
    top.fail("repeat_mm", "must be positive");
  const JsonObject cloth = top.object("cloth");
  cloth.read("name", info.cloth_name);
  cloth.read("hash", info.cloth_hash);
  cloth.read("source", info.source);
  const JsonObject o = top.object("optics");
  MaterialOptics& op = m.optics;
  o.read("depth_scale", op.depth_scale);
  o.read("extinction_per_mm", op.extinction_per_mm);
  std::string shading = "fiber", fiber_model = "table";
  o.read("shading", shading);
  o.read("fiber_model", fiber_model);
  if (shading != "fiber" && shading != "isotropic")
    o.fail(o.field("shading"), "must be \"fiber\" or \"isotropic\"");
  op.shading = shading == "isotropic" ? ShadingMode::Isotropic : ShadingMode::Fiber;
  if (fiber_model == "table") op.fiber_model = FiberModelKind::Table;
  else if (fiber_model == "ellipsoid") op.fiber_model = FiberModelKind::Ellipsoid;
  else if (fiber_model == "kajiya-kay") op.fiber_model = FiberModelKind::KajiyaKay;
  else o.fail(o.field("fiber_model"), "unknown fibre model \"" + fiber_model + "\"");
  o.read("isotropic_albedo", op.isotropic_albedo);
  o.read("fiber_samples", op.fiber_samples);
  o.read("fiber_seed", op.fiber_seed);
  o.read("step_cells", op.step_cells);
  o.read("cutoff", op.cutoff);
  o.read("light_roulette", op.light_roulette);
  if (!(op.depth_scale > 0.0f) || !std::isfinite(op.depth_scale))
    o.fail(o.field("depth_scale"), "must be positive");
  if (!(op.extinction_per_mm > 0.0f) || !std::isfinite(op.extinction_per_mm))
    o.fail(o.field("extinction_per_mm"), "must be positive");
  m.view_grid.k = s.directions;
  m.light_grid.k = s.light_directions;
  m.light_grid.map = s.light_map;
  top.read("max_rank", m.max_rank);
  if (m.max_rank < 0 || m.max_rank > m.light_count())
    top.fail("max_rank", "must be in [0, " + std::to_string(m.light_count()) + "]");
  int levels = 0;
  top.read("levels", levels);
  {
    // In memory: per level and view node, RGB floats per component and an
    // alpha (4/3 of level 0 over the pyramid), and the float light factors.
    const double texels = double(s.texels) * double(s.texels) * 4.0 / 3.0;
    const double bytes = double(m.view_count()) *
                         (texels * (12.0 * m.max_rank + 4.0) + 4.0 * m.light_count() * m.max_rank);
    if (bytes > double(memory_budget))
      top.fail("max_rank", "the table needs " + std::to_string(uint64_t(bytes) >> 20) +
                               " MiB in memory, over the budget of " +
                               std::to_string(memory_budget >> 20) + " MiB");
  }
  m.allocate();
  if (levels != m.levels())
    top.fail("levels", std::to_string(s.texels) + " texels give " + std::to_string(m.levels()) +
                           " levels, not " + std::to_string(levels));
  const json& ranks = top.raw("ranks");
  const json& errors = top.raw("errors");
  if (!ranks.is_array() || int(ranks.size()) != m.view_count())
    top.fail("ranks", "must list " + std::to_string(m.view_count()) + " view nodes");
  if (!errors.is_array() || int(errors.size()) != m.view_count())
    top.fail("errors", "must list " + std::to_string(m.view_count()) + " view nodes");
  for (int v = 0; v < m.view_count(); ++v) {
    if (!ranks[v].is_number_integer() || ranks[v].get<int>() < 0 ||
        ranks[v].get<int>() > m.max_rank)
      top.fail("ranks[" + std::to_string(v) + "]", "must be an integer in [0, max_rank]");
    if (!errors[v].is_number()) top.fail("errors[" + std::to_string(v) + "]", "must be a number");
    m.rank[v] = ranks[v].get<int>();
    m.error[v] = errors[v].get<float>();
  }
  // The images.
  const int K = s.directions;
  const std::vector<std::string> channels = level_channels(m.max_rank);
  const size_t nc = channels.size();
  for (int l = 0; l < m.levels(); ++l) {
    const int side = m.level_side(l);
    const int width = K * side, height = 2 * K * side;
    const std::vector<Imath::half> pixels = read_image<Imath::half>(
        (fs::path(dir) / level_file(l)).string(), width, height, channels, oiio::TypeDesc::HALF);
    const size_t texels = size_t(side) * side;
    for (int v = 0; v < m.view_count(); ++v)
      for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
          const size_t t = size_t(y) * side + x;
          const Imath::half* in = &pixels[atlas_pixel(v, x, y, side, K) * nc];
          m.alpha[l][size_t(v) * texels + t] = in[0];
          V3f* c = &m.coefficients[l][(size_t(v) * texels + t) * m.max_rank];
          for (int k = 0; k < m.max_rank; ++k) c[k] = V3f(in[1 + 3 * k], in[2 + 3 * k], in[3 + 3 * k]);
        }
  }
  std::vector<std::string> light_channels;
  for (int k = 0; k < std::max(1, m.max_rank); ++k) light_channels.push_back(component_name(k));
  const std::vector<float> lights =
      read_image<float>((fs::path(dir) / k_light_file).string(), m.light_count(), m.view_count(),
                        light_channels, oiio::TypeDesc::FLOAT);
  for (int v = 0; v < m.view_count(); ++v)
    for (int n = 0; n < m.light_count(); ++n)
      for (int k = 0; k < m.max_rank; ++k)
        m.light_factors[(size_t(v) * m.light_count() + n) * m.max_rank + k] =
            lights[(size_t(v) * m.light_count() + n) * light_channels.size() + k];
  return m;
}

}  // namespace clothbake::io
