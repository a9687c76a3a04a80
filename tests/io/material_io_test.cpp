#include "io/material_io.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/texture/volume_generator.h"
#include "core/util/error.h"
#include "core/weave/cloth_colours.h"
#include "io/data_image.h"

namespace clothbake::io {
namespace {

namespace fs = std::filesystem;
using Imath::V3f;

/// A small real material: the plain weave on a coarse grid, K = KL = 3.
const ClothMaterial& small_material() {
  static const ClothMaterial m = [] {
    ClothSpec spec;
    spec.resolution = {16, 16, 8, 1};
    const VolumeTexture volume = generate_volume(spec, uint64_t(1) << 32);
    const FiberShader shader(FiberModelKind::Table, 8.0f, 24.0f, 16, 1);
    MaterialSettings s;
    s.texels = 8;
    s.directions = 3;
    s.light_directions = 3;
    s.spp = 1;
    s.field_supersample = 1;
    s.max_error = 0.02f;
    return bake_material(material_source(volume, shader, MaterialOptics{}), s, uint64_t(1) << 32);
  }();
  return m;
}

MaterialInfo small_info() {
  MaterialInfo info;
  info.cloth_name = "plain";
  return info;
}

/// A tiny colour-free material of `spec` (16 x 16 x 8 cells, 2 x 2
/// directions, one sample), its cloth and palette set as `clothbake
/// material` sets them; `s` gives texels, address and context.
ClothMaterial small_colour_free(ClothSpec spec, MaterialSettings s) {
  spec.resolution = {16, 16, 8, 1};
  const ClothSpec free = colour_free(spec);
  const VolumeTexture volume = generate_volume(free, uint64_t(1) << 32);
  const FiberShader shader(FiberModelKind::Table, 8.0f, 24.0f, 16, 1);
  s.directions = 2;
  s.light_directions = 2;
  s.spp = 1;
  s.field_supersample = 1;
  s.parts = MaterialParts::SpecularWarpWeft;
  ClothMaterial m = bake_material(material_source(volume, shader, MaterialOptics{}, free), s,
                                  uint64_t(1) << 32, {}, nullptr);
  m.set_cloth(free, palette_of(spec));
  return m;
}

/// The 2/2 twill and the settings the addressed round trips bake it with.
ClothSpec twill() {
  ClothSpec spec;
  spec.pattern = "twill_2_2";
  return spec;
}

MaterialSettings addressed_settings() {
  MaterialSettings s;
  s.texels = 2;
  s.context = 1;
  s.address = MaterialAddress::Crossings;
  return s;
}

struct TempDir {
  fs::path path =
      fs::temp_directory_path() / ("clothbake_material_io_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  TempDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

std::string error_of(const std::string& dir) {
  MaterialInfo info;
  try {
    read_material(dir, info);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Everything written reads back: the table within half precision (the
// images are half floats; light factors are float and exact), every
// setting and optic exactly.
TEST(MaterialIo, RoundTrip) {
  TempDir tmp;
  const std::string dir = (tmp.path / "mat").string();
  const ClothMaterial& m = small_material();
  write_material(dir, m, small_info());
  EXPECT_TRUE(is_material_folder(dir));
  MaterialInfo info;
  const ClothMaterial r = read_material(dir, info);
  EXPECT_EQ(r.cloth_hash, m.cloth_hash);
  EXPECT_NE(r.cloth_hash, 0u);  // the volume's, set by the bake
  EXPECT_EQ(info.cloth_name, "plain");
  EXPECT_EQ(r.rank, m.rank);
  EXPECT_EQ(r.max_rank, m.max_rank);
  EXPECT_EQ(r.levels(), m.levels());
  EXPECT_EQ(r.light_factors, m.light_factors);
  EXPECT_EQ(r.optics.depth_scale, m.optics.depth_scale);
  EXPECT_EQ(r.repeat_mm, m.repeat_mm);
  // The coarse grid's cells are opaque (40 / mm x 1/16 mm: 2.5 per field
  // cell): auto baked it by the layer march, and the manifest says so.
  EXPECT_EQ(m.settings.light_fields, LightFieldMethod::LayerMarch);
  EXPECT_EQ(r.settings.light_fields, LightFieldMethod::LayerMarch);
  for (int l = 0; l < m.levels(); ++l) {
    ASSERT_EQ(r.coefficients[l].size(), m.coefficients[l].size());
    for (size_t i = 0; i < m.coefficients[l].size(); ++i)
      EXPECT_NEAR((r.coefficients[l][i] - m.coefficients[l][i]).length(), 0.0f,
                  1e-3f * (m.coefficients[l][i].length() + 1e-4f));
    for (size_t i = 0; i < m.alpha[l].size(); ++i) EXPECT_NEAR(r.alpha[l][i], m.alpha[l][i], 1e-3f);
  }
}

// A colour-free material (format version 2): its parts, its colour-free
// cloth spec (per-thread spacings included), its colours with a per-thread
// sequence, and the channel names; a version-1 manifest reads as RGB.
TEST(MaterialIo, ColourFreePartsRoundTrip) {
  TempDir tmp;
  ClothSpec spec;
  spec.warp.colors = {V3f(0.5f, 0.1f, 0.1f), V3f(0.1f, 0.4f, 0.1f), V3f(0.2f, 0.2f, 0.4f)};
  spec.weft.spacings_mm = {0.5f, 0.55f};
  MaterialSettings s;
  s.texels = 4;
  const ClothMaterial m = small_colour_free(spec, s);
  const std::string dir = (tmp.path / "mat").string();
  write_material(dir, m, small_info());
  MaterialInfo info;
  const ClothMaterial r = read_material(dir, info);
  EXPECT_TRUE(r.colour_parts());
  EXPECT_EQ(first_difference(r.cloth, m.cloth).field, "");
  EXPECT_EQ(r.cloth.weft.spacings_mm, spec.weft.spacings_mm);
  EXPECT_EQ(r.palette, m.palette);
  EXPECT_EQ(r.colours.warp.repeats, 3);
  EXPECT_EQ(r.colours.warp.levels[0], m.colours.warp.levels[0]);
  std::ifstream in(fs::path(dir) / "manifest.json");
  nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["version"], 2);
  EXPECT_EQ(j["parts"], "specular-warp-weft");
  EXPECT_EQ(j["cloth"]["threads"]["weft"]["centres_mm"].size(), 2u);
  // Version 1 (no parts): the same folder's manifest reads as RGB, and then
  // its images have five channels per component, not three: refused, naming
  // the file.
  j["version"] = 1;
  j.erase("parts");
  std::ofstream(fs::path(dir) / "manifest.json") << j.dump();
  const std::string err = error_of(dir);
  EXPECT_NE(err.find("level_0.exr"), std::string::npos) << err;
  EXPECT_NE(err.find("channels"), std::string::npos) << err;
}

// Addressed per crossing (version 3): the blocks and the index read back
// as written; a manifest whose counts or an index that disagrees with the
// classes the cloth spec gives is refused, naming the field or the file.
TEST(MaterialIo, AddressedPerCrossingRoundTrip) {
  TempDir tmp;
  ClothMaterial m = small_colour_free(twill(), addressed_settings());
  const std::string dir = (tmp.path / "mat").string();
  write_material(dir, m, small_info());
  MaterialInfo info;
  const ClothMaterial r = read_material(dir, info);
  ASSERT_TRUE(r.addressed());
  EXPECT_EQ(r.crossings.count(), 4);
  EXPECT_EQ(r.crossings.class_of, m.crossings.class_of);
  EXPECT_EQ(r.settings.context, 1);
  ASSERT_EQ(r.levels(), m.levels());
  for (int l = 0; l < r.levels(); ++l) {
    ASSERT_EQ(r.alpha[size_t(l)].size(), m.alpha[size_t(l)].size());
    for (size_t t = 0; t < r.alpha[size_t(l)].size(); ++t)
      EXPECT_NEAR(r.alpha[size_t(l)][t], m.alpha[size_t(l)][t], 1e-3f);  // stored as halves
  }
  const fs::path manifest = fs::path(dir) / "manifest.json";
  nlohmann::json j = nlohmann::json::parse(std::ifstream(manifest));
  EXPECT_EQ(j["version"], 3);
  EXPECT_EQ(j["address"], "crossings");
  EXPECT_EQ(j["crossings"]["blocks"], 4);
  // Counts that are not the spec's.
  nlohmann::json bad = j;
  bad["crossings"]["blocks"] = 3;
  std::ofstream(manifest) << bad.dump();
  std::string err = error_of(dir);
  EXPECT_NE(err.find("crossings.blocks"), std::string::npos) << err;
  // An index other than the spec's classes.
  std::ofstream(manifest) << j.dump();
  const int w = r.crossings.ends, h = r.crossings.picks;
  std::vector<float> index(size_t(w) * h, 0.0f);
  write_data_image((fs::path(dir) / "crossings.exr").string(), w, h, {"block"}, index.data());
  err = error_of(dir);
  EXPECT_NE(err.find("crossings.exr"), std::string::npos) << err;
  // An RGB material cannot be addressed per crossing.
  bad = j;
  bad["parts"] = "rgb";
  std::ofstream(manifest) << bad.dump();
  err = error_of(dir);
  EXPECT_NE(err.find("address"), std::string::npos) << err;
}

// A map's stretch between the texture's axes (optics.aspect) reads back
// exactly; an unstretched material writes none, so its manifest keeps the
// bytes it had before the aspect was kept, and reads back as 1.
TEST(MaterialIo, AStretchReadsBackAndNoneIsNotWritten) {
  TempDir tmp;
  const std::string plain = (tmp.path / "plain").string(),
                    stretched = (tmp.path / "stretched").string();
  ClothMaterial m = small_material();
  ASSERT_EQ(m.optics.aspect, 1.0f);
  write_material(plain, m, small_info());
  m.optics.aspect = 5.4129791f;
  write_material(stretched, m, small_info());
  auto manifest = [](const std::string& dir) {
    std::ifstream in(fs::path(dir) / "manifest.json");
    return nlohmann::json::parse(in);
  };
  EXPECT_FALSE(manifest(plain)["optics"].contains("aspect"));
  EXPECT_TRUE(manifest(stretched)["optics"].contains("aspect"));
  MaterialInfo info;
  EXPECT_EQ(read_material(plain, info).optics.aspect, 1.0f);
  EXPECT_EQ(read_material(stretched, info).optics.aspect, 5.4129791f);
}

// Phase bins (--phase-bins) read back and rebuild the same classes, more of
// them than the plain stencil gives; without bins nothing is written, so a
// material made before them keeps its bytes.
TEST(MaterialIo, PhaseBinsReadBackAndOneIsNotWritten) {
  TempDir tmp;
  MaterialSettings s = addressed_settings();
  const ClothMaterial plain = small_colour_free(twill(), s);
  s.phase_bins = 4;
  const ClothMaterial binned = small_colour_free(twill(), s);
  EXPECT_GT(binned.crossings.count(), plain.crossings.count());
  const std::string plain_dir = (tmp.path / "plain").string(),
                    binned_dir = (tmp.path / "binned").string();
  write_material(plain_dir, plain, small_info());
  write_material(binned_dir, binned, small_info());
  auto crossings = [](const std::string& dir) {
    std::ifstream in(fs::path(dir) / "manifest.json");
    return nlohmann::json::parse(in)["crossings"];
  };
  EXPECT_FALSE(crossings(plain_dir).contains("phase_bins"));
  EXPECT_EQ(crossings(binned_dir)["phase_bins"], 4);
  MaterialInfo info;
  const ClothMaterial r = read_material(binned_dir, info);
  EXPECT_EQ(r.settings.phase_bins, 4);
  EXPECT_EQ(r.crossings.class_of, binned.crossings.class_of);
  EXPECT_EQ(read_material(plain_dir, info).settings.phase_bins, 1);
}

TEST(MaterialIo, SameBytesTwice) {
  TempDir tmp;
  write_material((tmp.path / "a").string(), small_material(), small_info());
  write_material((tmp.path / "b").string(), small_material(), small_info());
  for (const auto& e : fs::directory_iterator(tmp.path / "a")) {
    std::ifstream fa(e.path(), std::ios::binary),
        fb(tmp.path / "b" / e.path().filename(), std::ios::binary);
    const std::string a((std::istreambuf_iterator<char>(fa)), {}),
        b((std::istreambuf_iterator<char>(fb)), {});
    EXPECT_EQ(a, b) << e.path().filename();
  }
}

// A damaged folder is refused with the file (and field) named.
TEST(MaterialIo, DamagedFoldersNameTheFileAndField) {
  TempDir tmp;
  const std::string good = (tmp.path / "good").string();
  write_material(good, small_material(), small_info());
  auto copy = [&](const std::string& name) {
    const fs::path p = tmp.path / name;
    fs::copy(good, p, fs::copy_options::recursive);
    return p;
  };
  auto edit_manifest = [&](const fs::path& dir, auto change) {
    std::ifstream in(dir / "manifest.json");
    nlohmann::json j = nlohmann::json::parse(in);
    change(j);
    std::ofstream(dir / "manifest.json") << j.dump(2);
  };
  {  // a truncated level image
    const fs::path d = copy("truncated");
    const fs::path level = d / "level_0.exr";
    fs::resize_file(level, fs::file_size(level) / 2);
    const std::string e = error_of(d.string());
    EXPECT_NE(e.find("level_0.exr"), std::string::npos) << e;
  }
  {  // a missing image
    const fs::path d = copy("missing");
    fs::remove(d / "light_factors.exr");
    const std::string e = error_of(d.string());
    EXPECT_NE(e.find("light_factors.exr: missing"), std::string::npos) << e;
  }
  {  // a corrupt manifest
    const fs::path d = copy("corrupt");
    std::ofstream(d / "manifest.json") << "{\"format\": \"clothbake-material\", ";
    EXPECT_NE(error_of(d.string()).find("manifest.json: malformed JSON"), std::string::npos)
        << error_of(d.string());
  }
  {  // texels out of range, not a power of two
    const fs::path d = copy("texels");
    edit_manifest(d, [](nlohmann::json& j) { j["texels"] = 48; });
    EXPECT_NE(error_of(d.string()).find("manifest.json: texels: must be a power of 2"),
              std::string::npos)
        << error_of(d.string());
  }
  {  // K out of range
    const fs::path d = copy("directions");
    edit_manifest(d, [](nlohmann::json& j) { j["light_directions"] = 99; });
    EXPECT_NE(error_of(d.string()).find("light_directions: must be in [2, 32]"), std::string::npos)
        << error_of(d.string());
  }
  {  // a rank above max_rank
    const fs::path d = copy("rank");
    edit_manifest(d, [](nlohmann::json& j) { j["ranks"][2] = 1000; });
    EXPECT_NE(error_of(d.string()).find("ranks[2]"), std::string::npos) << error_of(d.string());
  }
  {  // a manifest whose table would not fit in memory: refused before allocating
    const fs::path d = copy("huge");
    edit_manifest(d, [](nlohmann::json& j) {
      j["texels"] = 1024;
      j["levels"] = 11;
      j["directions"] = 32;
      j["light_directions"] = 32;
      j["max_rank"] = 2048;
      j["ranks"] = std::vector<int>(2048, 0);
      j["errors"] = std::vector<float>(2048, 0.0f);
    });
    EXPECT_NE(error_of(d.string()).find("max_rank: the table needs"), std::string::npos)
        << error_of(d.string());
  }
  {  // another format
    const fs::path d = copy("format");
    edit_manifest(d, [](nlohmann::json& j) { j["format"] = "clothbake-lookup"; });
    EXPECT_NE(error_of(d.string()).find("format: expected \"clothbake-material\""),
              std::string::npos)
        << error_of(d.string());
  }
  {  // images of the wrong size for the manifest
    const fs::path d = copy("size");
    edit_manifest(d, [](nlohmann::json& j) {
      j["directions"] = 4;
      j["ranks"] = std::vector<int>(32, 0);
      j["errors"] = std::vector<float>(32, 0.0f);
    });
    EXPECT_NE(error_of(d.string()).find("level_0.exr: is"), std::string::npos)
        << error_of(d.string());
  }
}

// A destination that is not a material (or lookup) folder is never replaced,
// and a failed write leaves the previous material as it was.
TEST(MaterialIo, NeverReplacesAnotherFolder) {
  TempDir tmp;
  const fs::path other = tmp.path / "photos";
  fs::create_directories(other);
  std::ofstream(other / "keep.jpg") << "x";
  EXPECT_THROW(write_material(other.string(), small_material(), small_info()), InputError);
  EXPECT_TRUE(fs::exists(other / "keep.jpg"));
  EXPECT_FALSE(fs::exists(other / "manifest.json"));
}

}  // namespace
}  // namespace clothbake::io
