#include "io/lookup_io.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <sstream>

#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "io/light_json.h"

namespace clothbake::io {
namespace {

namespace fs = std::filesystem;
using Imath::V3f;
using nlohmann::json;

constexpr int kK = 3;

// Nodes each quad bakes in the whole table: both sides in use, node 8 (the
// last of the front side) and most of the back side baked by no quad.
const std::vector<std::vector<int>> kBakedNodes = {{0, 4, 13}, {4, 5}, {17}};
// The same without back-side nodes.
const std::vector<std::vector<int>> kFrontNodes = {{0, 4}, {4, 5}, {1}};
const std::vector<int> kSizes = {4, 3, 2};

float texel_value(int q, int node, int a, int b, int c) {
  return float((q + 1) * 1000 + node * 37 + a * 7 + b * 3 + c) / 64.0f - 20.0f;
}

/// The lookup of three quads that a bake of the quads in `quads` would
/// produce: the whole bake's layout (squares for every node of `nodes`),
/// flags only for those quads, their texels, gutters.
LookupTable make_table(const std::set<int>& quads,
                       const std::vector<std::vector<int>>& nodes = kBakedNodes,
                       const std::vector<int>& sizes = kSizes) {
  LookupTable t;
  t.dirs.k = kK;
  t.gutter = 1;
  t.sizes = sizes;
  std::vector<uint8_t> wanted(t.sizes.size() * size_t(t.node_count()), 0);
  for (size_t q = 0; q < nodes.size(); ++q)
    for (int node : nodes[q]) wanted[q * t.node_count() + node] = 1;
  t.pack(wanted);
  t.baked.assign(wanted.size(), 0);
  for (int q : quads)
    for (int node : nodes[q]) t.baked[size_t(q) * t.node_count() + node] = 1;
  t.allocate_atlases();
  for (int q : quads)
    for (int node : nodes[q])
      for (int b = 0; b < t.sizes[q]; ++b)
        for (int a = 0; a < t.sizes[q]; ++a)
          for (int c = 0; c < 4; ++c)
            t.texel(q, node, a, b)[c] = Imath::half(texel_value(q, node, a, b, c));
  t.fill_gutters();
  return t;
}

Scene make_scene() {
  Scene scene;
  ClothObject object;
  object.name = "cloth";
  object.mesh.positions_world = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  object.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  object.mesh.quads = {{{0, 1, 2, 3}, {0, 1, 2, 3}}};
  scene.objects.push_back(object);
  Light sun;
  sun.to_light_world = {0, 0.6f, 0.8f};
  sun.intensity = 2.0f;
  scene.lights.push_back(sun);
  Light lamp;
  lamp.type = LightType::Point;
  lamp.position_world = {1, 2, 3};
  lamp.color = {1, 0.5f, 0.25f};
  scene.lights.push_back(lamp);
  return scene;
}

LookupInfo make_info(const Scene& scene) {
  LookupInfo info;
  info.scene_path = "scenes/test.json";
  info.scene_hash = scene_fingerprint(scene);
  info.cloth_hashes = {"0123456789abcdef"};
  info.quad_counts = {3};
  info.meshes = {summarize_mesh(scene.objects[0].mesh)};
  info.settings.directions = kK;
  info.settings.texels = 4;
  info.settings.spp = 2;
  info.settings.adaptive = true;
  info.settings.texels_per_pixel = 0.75f;
  info.settings.min_texels = 2;
  info.settings.max_texels = 8;
  info.settings.seed = 1234567890123ull;
  info.statistics = {{"bake_seconds", 1.5}};
  return info;
}

void expect_same_tables(const LookupTable& a, const LookupTable& b) {
  EXPECT_EQ(a.dirs.k, b.dirs.k);
  EXPECT_EQ(a.gutter, b.gutter);
  EXPECT_EQ(a.sizes, b.sizes);
  EXPECT_EQ(a.baked, b.baked);
  ASSERT_EQ(a.slots.size(), b.slots.size());
  for (size_t i = 0; i < a.slots.size(); ++i) {
    EXPECT_EQ(a.slots[i].x, b.slots[i].x) << i;
    EXPECT_EQ(a.slots[i].y, b.slots[i].y) << i;
  }
  for (int side = 0; side < 2; ++side) {
    const LookupAtlas &aa = a.atlases[side], &ab = b.atlases[side];
    EXPECT_EQ(aa.width, ab.width) << side;
    EXPECT_EQ(aa.height, ab.height) << side;
    ASSERT_EQ(aa.pixels.size(), ab.pixels.size()) << "side " << side;
    size_t differing = 0;
    for (size_t i = 0; i < aa.pixels.size(); ++i)
      differing += aa.pixels[i].bits() != ab.pixels[i].bits();
    EXPECT_EQ(differing, 0u) << "side " << side;
  }
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class LookupIo : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("clothbake_lookup_test_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(m_dir, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(m_dir);
  }
  // Entries of m_dir whose names contain ".tmp-" or ".old-".
  std::vector<std::string> leftovers() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(m_dir)) {
      const std::string name = e.path().filename().string();
      if (name.find(".tmp-") != std::string::npos || name.find(".old-") != std::string::npos)
        out.push_back(name);
    }
    return out;
  }
  // Writes the whole table to `name`, edits its manifest with `edit`.
  std::string write_whole(const std::string& name,
                          const std::function<void(json&)>& edit = {}) const {
    const std::string dir = (m_dir / name).string();
    const Scene scene = make_scene();
    write_lookup(dir, {make_table({0, 1, 2})}, make_info(scene), scene);
    if (edit) {
      const fs::path manifest = fs::path(dir) / "manifest.json";
      json m = json::parse(file_bytes(manifest));
      edit(m);
      std::ofstream(manifest, std::ios::binary) << m.dump(2);
    }
    return dir;
  }
  // Reading `dir`: "file | field | message" of the error, or "(no error)".
  static std::string error_of(const std::string& dir, const std::string& expected_hash = {}) {
    LookupInfo info;
    try {
      (void)read_lookup(dir, info, expected_hash);
    } catch (const InputError& e) {
      return e.file() + " | " + e.field() + " | " + e.message();
    }
    return "(no error)";
  }
  fs::path m_dir;
};

TEST_F(LookupIo, RoundTripKeepsEveryHalfAndField) {
  const Scene scene = make_scene();
  const LookupTable table = make_table({0, 1, 2});
  const LookupInfo info = make_info(scene);
  const std::string dir = (m_dir / "bake").string();
  write_lookup(dir, {table}, info, scene);

  LookupInfo back;
  const std::vector<LookupTable> tables = read_lookup(dir, back, info.scene_hash);
  ASSERT_EQ(tables.size(), 1u);
  expect_same_tables(table, tables[0]);
  for (int q = 0; q < 3; ++q) EXPECT_FALSE(tables[0].slot(q, 8).valid());  // nobody bakes node 8
  EXPECT_EQ(back.scene_path, info.scene_path);
  EXPECT_EQ(back.scene_hash, info.scene_hash);
  EXPECT_EQ(back.cloth_hashes, info.cloth_hashes);
  EXPECT_EQ(back.quad_counts, std::vector<int>{3});
  ASSERT_EQ(back.meshes.size(), 1u);
  ASSERT_TRUE(back.meshes[0].has_value());
  const MeshSummary& got = *back.meshes[0];
  const MeshSummary& e = *info.meshes[0];
  EXPECT_EQ(got.bounds_min_world, e.bounds_min_world);
  EXPECT_EQ(got.bounds_max_world, e.bounds_max_world);
  EXPECT_EQ(got.uv_min, e.uv_min);
  EXPECT_EQ(got.uv_max, e.uv_max);
  EXPECT_EQ(got.mean_centre_world, e.mean_centre_world);
  EXPECT_NEAR(got.area_world, e.area_world, 1e-6 * e.area_world);  // a float in the file
  EXPECT_EQ(back.settings.directions, kK);
  EXPECT_EQ(back.settings.texels, 4);
  EXPECT_EQ(back.settings.spp, 2);
  EXPECT_TRUE(back.settings.adaptive);
  EXPECT_EQ(back.settings.texels_per_pixel, 0.75f);
  EXPECT_EQ(back.settings.min_texels, 2);
  EXPECT_EQ(back.settings.max_texels, 8);
  EXPECT_EQ(back.settings.quad_begin, 0);
  EXPECT_EQ(back.settings.quad_end, -1);
  EXPECT_EQ(back.settings.seed, 1234567890123ull);
  EXPECT_EQ(back.statistics, info.statistics);

  // The manifest as documented.
  const json m = json::parse(file_bytes(fs::path(dir) / "manifest.json"));
  EXPECT_EQ(m["format"], "clothbake-lookup");
  EXPECT_EQ(m["version"], 2);
  EXPECT_EQ(m["direction_map"]["k"], kK);
  EXPECT_EQ(m["lights"].size(), 2u);
  EXPECT_EQ(m["lights"][0]["type"], "directional");
  EXPECT_EQ(m["lights"][1]["position"], json::array({1.0f, 2.0f, 3.0f}));
  const json& o = m["objects"][0];
  EXPECT_EQ(o["name"], "cloth");
  EXPECT_EQ(o["sizes"], json::array({4, 3, 2}));
  EXPECT_EQ(o["baked"][1], "000011000000000000");
  EXPECT_EQ(o["sides"]["front"]["file"], "object0_side0.exr");
  EXPECT_EQ(o["sides"]["back"]["file"], "object0_side1.exr");
  // Squares: every (quad, node) of the whole layout, once, front nodes on the front.
  EXPECT_EQ(o["sides"]["front"]["squares"].size(), 4u);  // (0,0) (0,4) (1,4) (1,5)
  EXPECT_EQ(o["sides"]["back"]["squares"].size(), 2u);   // (0,13) (2,17)
  EXPECT_EQ(lookup_bytes(tables), table.atlas_bytes());
  // Packed: the back atlas holds a 4 x 4 and a 2 x 2 square with gutters only.
  EXPECT_LE(table.atlases[1].width * table.atlases[1].height, 2 * (6 * 6 + 4 * 4));

  // The atlas: texel (a, b) of (quad, node) at the square's (x + a, y + b).
  auto in = OIIO::ImageInput::open((fs::path(dir) / "object0_side1.exr").string());
  ASSERT_TRUE(in);
  const int w = table.atlases[1].width, h = table.atlases[1].height;
  EXPECT_EQ(in->spec().width, w);
  EXPECT_EQ(in->spec().height, h);
  EXPECT_EQ(o["sides"]["back"]["size"], json::array({w, h}));
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::HALF);
  EXPECT_EQ(in->spec().get_string_attribute("DateTime"), "");  // same bytes on every write
  std::vector<Imath::half> pixels(size_t(w) * h * 4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::HALF, pixels.data()));
  json square;
  for (const json& sq : o["sides"]["back"]["squares"])
    if (sq[0] == 0 && sq[1] == 13) square = sq;
  ASSERT_FALSE(square.is_null());
  const int x = square[2].get<int>() + 1, y = square[3].get<int>() + 2;  // texel (1, 2)
  const size_t at = (size_t(y) * w + x) * 4;
  EXPECT_EQ(float(pixels[at + 2]), float(Imath::half(texel_value(0, 13, 1, 2, 2))));
}

TEST_F(LookupIo, UnbakedSideHasNoFile) {
  const Scene scene = make_scene();
  const LookupTable table = make_table({0, 1, 2}, kFrontNodes);  // no back-side node at all
  const std::string dir = (m_dir / "front_only").string();
  write_lookup(dir, {table}, make_info(scene), scene);
  EXPECT_TRUE(fs::exists(fs::path(dir) / "object0_side0.exr"));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "object0_side1.exr"));
  const json m = json::parse(file_bytes(fs::path(dir) / "manifest.json"));
  EXPECT_TRUE(m["objects"][0]["sides"]["back"].is_null());
  LookupInfo back;
  expect_same_tables(table, read_lookup(dir, back)[0]);
  EXPECT_EQ(lookup_bytes({table}),
            uint64_t(table.atlases[0].width) * table.atlases[0].height * 4 * 2);
}

TEST_F(LookupIo, WritingOverAFolderReplacesItAndLeavesNoTemporaries) {
  const Scene scene = make_scene();
  const std::string dir = write_whole("bake");
  std::ofstream(fs::path(dir) / "stray.txt") << "from before";
  const LookupTable front_only = make_table({1}, kFrontNodes);
  write_lookup(dir, {front_only}, make_info(scene), scene);
  LookupInfo back;
  expect_same_tables(front_only, read_lookup(dir, back)[0]);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "object0_side1.exr"));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "stray.txt"));
  EXPECT_TRUE(leftovers().empty());
  // A trailing slash names the same folder.
  write_lookup(dir + "/", {make_table({0, 1, 2})}, make_info(scene), scene);
  EXPECT_TRUE(fs::exists(fs::path(dir) / "object0_side1.exr"));
  EXPECT_TRUE(leftovers().empty());
}

TEST_F(LookupIo, FailureMidWriteLeavesTheFolderIntact) {
  const Scene scene = make_scene();
  const std::string dir = write_whole("bake");
  const std::string before = file_bytes(fs::path(dir) / "object0_side0.exr");
  // The back side's atlas is broken: refused before anything replaces `dir`.
  LookupTable broken = make_table({0, 1, 2});
  broken.atlases[1].pixels.resize(5);
  EXPECT_THROW(write_lookup(dir, {broken}, make_info(scene), scene), InputError);
  EXPECT_TRUE(leftovers().empty());
  EXPECT_EQ(error_of(dir), "(no error)");
  EXPECT_EQ(file_bytes(fs::path(dir) / "object0_side0.exr"), before);
}

TEST_F(LookupIo, UnwritableParentLeavesTheFolderIntact) {
  if (::geteuid() == 0) GTEST_SKIP() << "root can write anywhere";
  const Scene scene = make_scene();
  const std::string dir = write_whole("bake");
  fs::permissions(m_dir, fs::perms::owner_write, fs::perm_options::remove);
  EXPECT_THROW(write_lookup(dir, {make_table({1})}, make_info(scene), scene), InputError);
  fs::permissions(m_dir, fs::perms::owner_write, fs::perm_options::add);
  EXPECT_TRUE(fs::exists(fs::path(dir) / "object0_side1.exr"));
  EXPECT_EQ(error_of(dir), "(no error)");
}

TEST_F(LookupIo, RefusesToReplaceAFolderThatIsNotALookup) {
  const Scene scene = make_scene();
  fs::create_directories(m_dir / "photos");
  std::ofstream(m_dir / "photos" / "a.jpg") << "x";
  try {
    write_lookup((m_dir / "photos").string(), {make_table({1})}, make_info(scene), scene);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("not a lookup folder"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(m_dir / "photos" / "a.jpg"));
}

TEST_F(LookupIo, ManifestErrorsNameTheFileAndField) {
  auto manifest = [](const std::string& dir) { return dir + "/manifest.json"; };
  std::string dir = write_whole("version", [](json& m) { m["version"] = 1; });
  EXPECT_EQ(error_of(dir), manifest(dir) +
                               " | version | this lookup has format version 1; this clothbake "
                               "reads version 2");

  dir = write_whole("format", [](json& m) { m["format"] = "something-else"; });
  EXPECT_EQ(error_of(dir).rfind(manifest(dir) + " | format | ", 0), 0u) << error_of(dir);

  dir = write_whole("k", [](json& m) { m["direction_map"]["k"] = 65; });
  EXPECT_EQ(error_of(dir), manifest(dir) + " | direction_map.k | must be in [2, 64], got 65");

  dir = write_whole("baked", [](json& m) { m["objects"][0]["baked"][1] = "00001100000000000x"; });
  EXPECT_EQ(error_of(dir).rfind(manifest(dir) + " | objects[0].baked[1] | ", 0), 0u)
      << error_of(dir);
  dir = write_whole("baked_length", [](json& m) { m["objects"][0]["baked"][2] = "0101"; });
  EXPECT_EQ(error_of(dir).rfind(manifest(dir) + " | objects[0].baked[2] | ", 0), 0u)
      << error_of(dir);

  dir = write_whole("square",
                    [](json& m) { m["objects"][0]["sides"]["back"]["squares"][1][2] = 99; });
  EXPECT_EQ(error_of(dir).rfind(manifest(dir) +
                                    " | objects[0].sides.back.squares[1] | the square and its "
                                    "gutter do not fit in the ",
                                0),
            0u)
      << error_of(dir);
  dir = write_whole("square_node",
                    [](json& m) { m["objects"][0]["sides"]["back"]["squares"][0][1] = 3; });
  EXPECT_EQ(error_of(dir), manifest(dir) +
                               " | objects[0].sides.back.squares[0] | node 3 is not a node of "
                               "the back side");
  dir =
      write_whole("no_square", [](json& m) { m["objects"][0]["baked"][2] = "000000000000000011"; });
  EXPECT_EQ(error_of(dir), manifest(dir) +
                               " | objects[0].baked[2] | node 16 is marked baked but has no "
                               "square in objects[0].sides.back.squares");

  dir = write_whole("hash");
  EXPECT_EQ(error_of(dir, "ffffffffffffffff"),
            manifest(dir) + " | scene_hash | this lookup was baked for another scene (hash " +
                make_info(make_scene()).scene_hash + ", expected ffffffffffffffff); bake again");

  dir = write_whole("missing_exr");
  fs::remove(fs::path(dir) / "object0_side1.exr");
  EXPECT_EQ(error_of(dir).rfind(dir + "/object0_side1.exr |  | cannot read", 0), 0u)
      << error_of(dir);

  dir = write_whole("truncated_exr");
  const fs::path exr = fs::path(dir) / "object0_side0.exr";
  fs::resize_file(exr, fs::file_size(exr) / 2);
  EXPECT_EQ(error_of(dir).rfind(exr.string() + " |  | cannot read", 0), 0u) << error_of(dir);

  // The manifest promises a bigger atlas than the image has.
  dir = write_whole("size", [](json& m) {
    json& size = m["objects"][0]["sides"]["front"]["size"];
    size[0] = size[0].get<int>() + 1;
  });
  EXPECT_NE(error_of(dir).find("/object0_side0.exr |  | is "), std::string::npos) << error_of(dir);
  EXPECT_NE(error_of(dir).find("pixels; the manifest (objects[0].sides.front.size) says "),
            std::string::npos)
      << error_of(dir);
}

TEST_F(LookupIo, MergeOfPartsEqualsTheWholeBakeByteForByte) {
  const Scene scene = make_scene();
  LookupInfo part_info = make_info(scene);
  const std::string a = (m_dir / "a").string(), b = (m_dir / "b").string();
  part_info.settings.quad_begin = 0;
  part_info.settings.quad_end = 1;
  write_lookup(a, {make_table({0})}, part_info, scene);
  part_info.settings.quad_begin = 1;
  part_info.settings.quad_end = 3;  // as `bake --quads 1-2` records it
  write_lookup(b, {make_table({1, 2})}, part_info, scene);

  LookupInfo merged_info;
  const std::vector<LookupTable> merged = merge_lookups({a, b}, merged_info);
  ASSERT_EQ(merged.size(), 1u);
  const LookupTable whole = make_table({0, 1, 2});
  expect_same_tables(whole, merged[0]);
  EXPECT_EQ(merged_info.settings.quad_begin, 0);
  EXPECT_EQ(merged_info.settings.quad_end, -1);
  EXPECT_EQ(merged_info.scene_hash, scene_fingerprint(scene));

  const std::string merged_dir = (m_dir / "merged").string();
  const std::string whole_dir = (m_dir / "whole").string();
  write_lookup(merged_dir, merged, merged_info, read_lookup_scene(a));
  write_lookup(whole_dir, {whole}, make_info(scene), scene);
  for (const char* name : {"object0_side0.exr", "object0_side1.exr"})
    EXPECT_EQ(file_bytes(fs::path(merged_dir) / name), file_bytes(fs::path(whole_dir) / name))
        << name;
  // The manifests differ only in the statistics.
  json m_merged = json::parse(file_bytes(fs::path(merged_dir) / "manifest.json"));
  json m_whole = json::parse(file_bytes(fs::path(whole_dir) / "manifest.json"));
  m_merged.erase("statistics");
  m_whole.erase("statistics");
  EXPECT_EQ(m_merged, m_whole);

  // Overlapping parts give the same result.
  write_lookup(a, {make_table({0, 1})}, part_info, scene);
  expect_same_tables(whole, merge_lookups({a, b}, merged_info)[0]);
}

TEST_F(LookupIo, MergeRefusesPartsOfAnotherScene) {
  const Scene scene = make_scene();
  const std::string a = (m_dir / "parts" / "a").string(), b = (m_dir / "parts" / "b").string();
  LookupInfo info = make_info(scene);
  write_lookup(a, {make_table({0})}, info, scene);
  info.scene_hash = "0000000000000000";
  write_lookup(b, {make_table({1})}, info, scene);
  LookupInfo merged;
  try {
    (void)merge_lookups({a, b}, merged);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), b + "/manifest.json");
    EXPECT_EQ(e.message().rfind("scene_hash differs from " + a + "/manifest.json", 0), 0u)
        << e.what();
  }

  // Same scene, another layout.
  info = make_info(scene);
  const LookupTable moved = make_table({1}, kBakedNodes, {4, 3, 3});
  write_lookup(b, {moved}, info, scene);
  try {
    (void)merge_lookups({a, b}, merged);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), b + "/manifest.json");
    EXPECT_EQ(e.message(), "objects[0].sizes differs from " + a +
                               "/manifest.json; parts to merge must come from one scene and "
                               "one bake");
  }
}

// Lookups written before objects[o].mesh was recorded have none: still read,
// with no summary (the add-on then checks the quad count only).
TEST_F(LookupIo, ManifestWithoutMeshSummaryStillReads) {
  const Scene scene = make_scene();
  LookupInfo info = make_info(scene);
  info.meshes.clear();
  const std::string dir = (m_dir / "bake").string();
  write_lookup(dir, {make_table({0, 1, 2})}, info, scene);
  std::ifstream in(fs::path(dir) / "manifest.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("\"mesh\""), std::string::npos);
  LookupInfo back;
  read_lookup(dir, back, info.scene_hash);
  ASSERT_EQ(back.meshes.size(), 1u);
  EXPECT_FALSE(back.meshes[0].has_value());
}

TEST_F(LookupIo, SceneFingerprintFollowsWhatABakeComputes) {
  const Scene base = make_scene();
  const std::string h = scene_fingerprint(base);
  ASSERT_EQ(h.size(), 16u);
  EXPECT_EQ(h.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_EQ(scene_fingerprint(make_scene()), h);

  auto changed = [&](const std::function<void(Scene&)>& edit) {
    Scene s = make_scene();
    edit(s);
    return scene_fingerprint(s) != h;
  };
  EXPECT_TRUE(changed([](Scene& s) { s.lights[0].intensity = 2.5f; }));
  EXPECT_TRUE(changed([](Scene& s) { s.lights[1].position_world.x += 0.01f; }));
  EXPECT_TRUE(changed([](Scene& s) { s.lights.pop_back(); }));
  EXPECT_TRUE(changed([](Scene& s) { s.objects[0].mesh.positions_world[2].z = 0.001f; }));
  EXPECT_TRUE(changed([](Scene& s) { s.objects[0].mesh.uvs[1].x = 2.0f; }));
  EXPECT_TRUE(changed([](Scene& s) { s.objects[0].cloth.seed = 2; }));
  EXPECT_TRUE(changed([](Scene& s) { s.objects[0].cloth.weft.twist_deg = 10.0f; }));
  EXPECT_TRUE(changed([](Scene& s) { s.objects[0].cloth.draft = {{1, 0}, {0, 1}}; }));
  EXPECT_TRUE(changed([](Scene& s) { s.objects[0].thickness_world = 0.02f; }));
  EXPECT_TRUE(changed([](Scene& s) { s.settings.step_cells = 0.25f; }));
  // The light roulette changes a bake's bytes (not its expectation), as the seed does.
  EXPECT_TRUE(changed([](Scene& s) { s.settings.light_roulette = 0.0f; }));

  EXPECT_FALSE(changed([](Scene& s) { s.settings.spp = 64; }));
  EXPECT_FALSE(changed([](Scene& s) {
    s.camera.position_world = {3, 2, 1};
    s.camera.fov_deg = 20.0f;
    s.camera.width = 64;
  }));
  // What a directional light does not use.
  EXPECT_FALSE(changed([](Scene& s) { s.lights[0].position_world = {9, 9, 9}; }));
  EXPECT_FALSE(changed([](Scene& s) { s.lights[1].axis_world = {1, 0, 0}; }));
  // What a spot and an area light use.
  auto with = [](LightType type) {
    return [type](Scene& s) {
      s.lights[1].type = type;
      return s;
    };
  };
  for (LightType type : {LightType::Spot, LightType::Area}) {
    Scene s = make_scene();
    const std::string typed = scene_fingerprint(with(type)(s));
    EXPECT_NE(typed, h);
    auto changed_typed = [&](const std::function<void(Scene&)>& edit) {
      Scene t = make_scene();
      with(type)(t);
      edit(t);
      return scene_fingerprint(t) != typed;
    };
    EXPECT_TRUE(changed_typed([](Scene& t) { t.lights[1].axis_world = {1, 0, 0}; }));
    EXPECT_EQ(changed_typed([](Scene& t) { t.lights[1].spot_smooth = 0.3f; }),
              type == LightType::Spot);
    EXPECT_EQ(changed_typed([](Scene& t) { t.lights[1].spot_cos_half_angle = 0.3f; }),
              type == LightType::Spot);
    EXPECT_EQ(changed_typed([](Scene& t) { t.lights[1].area_width = 0.3f; }),
              type == LightType::Area);
    EXPECT_EQ(changed_typed([](Scene& t) { t.lights[1].area_height = 0.3f; }),
              type == LightType::Area);
    EXPECT_EQ(changed_typed([](Scene& t) { t.lights[1].side_world = {0, 0, 1}; }),
              type == LightType::Area);
    EXPECT_EQ(changed_typed([](Scene& t) { t.lights[1].area_shape = AreaShape::Ellipse; }),
              type == LightType::Area);
  }
}

// Every light type's stored spelling reads back bit for bit (a merge writes
// the manifest's lights again).
TEST(LightJson, StoredSpellingRoundTrips) {
  Light spot;
  spot.type = LightType::Spot;
  spot.position_world = {0.1f, 0.2f, 3.3f};
  spot.axis_world = V3f(0.3f, -0.1f, -1.0f).normalized();
  spot.spot_cos_half_angle = 0.8660254f;
  spot.spot_smooth = 0.0200957f;
  spot.color = {1, 0.9f, 0.7f};
  spot.intensity = 12.5f;
  Light area;
  area.type = LightType::Area;
  area.position_world = {1.0f, -2.0f, 3.0f};
  area.axis_world = V3f(0.0f, 0.6f, -0.8f);
  area.side_world = V3f(1.0f, 0.0f, 0.0f);
  area.area_shape = AreaShape::Ellipse;
  area.area_width = 0.7f;
  area.area_height = 0.3f;
  area.intensity = 3.0f;
  for (const Light& l : {spot, area}) {
    const json j = stored_light_json(l);
    const Light back = read_light(JsonObject(j, "lights[0]", "m.json"), LightSpelling::Stored);
    EXPECT_EQ(stored_light_json(back), j);
    EXPECT_EQ(back.type, l.type);
    EXPECT_EQ(back.axis_world, l.axis_world);
    EXPECT_EQ(back.position_world, l.position_world);
    EXPECT_EQ(back.spot_cos_half_angle, l.spot_cos_half_angle);
    EXPECT_EQ(back.spot_smooth, l.spot_smooth);
    EXPECT_EQ(back.side_world, l.side_world);
    EXPECT_EQ(back.area_shape, l.area_shape);
    EXPECT_EQ(back.area_width, l.area_width);
    EXPECT_EQ(back.area_height, l.area_height);
  }
}

}  // namespace
}  // namespace clothbake::io
