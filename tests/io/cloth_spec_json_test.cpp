#include "io/cloth_spec_json.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace clothbake::io {
namespace {

namespace fs = std::filesystem;

class ClothSpecJson : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("clothbake_spec_test_" +
             std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = m_dir / name;
    std::ofstream(p) << text;
    return p.string();
  }
  // Loads and returns the error text, or "(no error)".
  std::string error_of(const std::string& text) {
    const std::string path = write("spec.json", text);
    try {
      (void)load_cloth_spec(path);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return e.field() + " | " + e.message();
    }
    return "(no error)";
  }
  fs::path m_dir;
};

TEST_F(ClothSpecJson, ReadsThePaperCloth) {
  const ClothSpec s = load_cloth_spec(CLOTHBAKE_SOURCE_DIR "/testscenes/paper/cloth.json");
  EXPECT_EQ(s.pattern, "plain");
  EXPECT_FLOAT_EQ(s.warp.spacing_mm, 0.5f);
  EXPECT_FLOAT_EQ(s.weft.color.y, 0.42f);
  EXPECT_EQ(s.resolution.cells_x, 64);
  EXPECT_EQ(s.seed, 1u);
}

TEST_F(ClothSpecJson, AbsentKeysKeepDefaults) {
  const ClothSpec s = load_cloth_spec(write("spec.json", R"({"warp": {"twist_deg": 12}})"));
  const ClothSpec d;
  EXPECT_FLOAT_EQ(s.warp.twist_deg, 12.0f);
  EXPECT_FLOAT_EQ(s.warp.width_mm, d.warp.width_mm);
  EXPECT_EQ(s.resolution.layers, d.resolution.layers);
}

TEST_F(ClothSpecJson, ReadsACustomDraft) {
  const ClothSpec s =
      load_cloth_spec(write("spec.json", R"({"weave": {"draft": [[1,0,0],[0,1,0],[0,0,1]]}})"));
  ASSERT_EQ(s.draft.size(), 3u);
  EXPECT_EQ(s.draft[1][1], 1);
}

TEST_F(ClothSpecJson, ErrorsNameTheField) {
  EXPECT_EQ(error_of(R"({"warp": {"width_mm": "wide"}})"),
            "warp.width_mm | expected a number, got a string");
  EXPECT_EQ(error_of(R"({"warp": {"widht_mm": 0.3}})").substr(0, 24), "warp.widht_mm | unknown ");
  EXPECT_EQ(error_of(R"({"resolution": {"layers": 2.5}})"),
            "resolution.layers | expected an integer, got a number with a fraction");
  EXPECT_EQ(error_of(R"({"weave": {"pattern": "tartan"}})").substr(0, 32),
            "weave.pattern | unknown weave 't");
  EXPECT_EQ(error_of(R"({"weave": {"draft": [[1,0],[0,2]]}})").substr(0, 21),
            "weave.draft[1][1] | e");
  EXPECT_EQ(error_of(R"({"weave": {"draft": []}})"), "weave.draft | the draft is empty");
  EXPECT_EQ(error_of(R"({"weft": {"thickness_mm": -0.1}})").substr(0, 35),
            "weft.thickness_mm | must be greater");
  EXPECT_EQ(error_of(R"({"crimp": 1e999})"),
            " | invalid JSON: number overflow parsing '1e999' (numbers must be finite)");
  EXPECT_EQ(error_of(R"({"warp": {"color": [1, 0]}})"),
            "warp.color | expected an array of three numbers, got an array of 2");
}

TEST_F(ClothSpecJson, SyntaxErrorsGiveLineAndColumn) {
  const std::string e = error_of("{\n  \"crimp\": 1.0,\n}\n");
  EXPECT_NE(e.find("malformed JSON at line 3"), std::string::npos) << e;
}

TEST_F(ClothSpecJson, MissingFileIsNamed) {
  try {
    (void)load_cloth_spec((m_dir / "nope.json").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (m_dir / "nope.json").string());
    EXPECT_NE(e.message().find("cannot open"), std::string::npos);
  }
}

TEST_F(ClothSpecJson, SceneUsesItsFirstObjectsCloth) {
  const std::string inline_scene =
      write("scene.json", R"({"objects": [{"cloth": {"weave": {"pattern": "satin_5"}}}]})");
  EXPECT_EQ(load_cloth_spec(inline_scene).pattern, "satin_5");
  write("c.json", R"({"weave": {"pattern": "twill_2_2"}})");
  const std::string by_file = write("scene2.json", R"({"objects": [{"cloth": "c.json"}]})");
  EXPECT_EQ(load_cloth_spec(by_file).pattern, "twill_2_2");
  // Errors inside a scene's inline cloth carry the full path.
  const std::string bad = write("scene3.json", R"({"objects": [{"cloth": {"crimp": -1}}]})");
  try {
    (void)load_cloth_spec(bad);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "objects[0].cloth.crimp");
  }
}

// A scene's cloth file must be a cloth spec: a scene naming itself (or
// another scene) used to recurse until the stack overflowed.
TEST_F(ClothSpecJson, SceneNamingASceneAsItsClothIsRefused) {
  const std::string self = write("self.json", R"({"objects": [{"cloth": "self.json"}]})");
  try {
    (void)load_cloth_spec(self);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), self);
    EXPECT_EQ(e.field(), "objects");
    EXPECT_NE(e.message().find("unknown key"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace clothbake::io
