#include "io/scene_json.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "core/texture/volume_generator.h"
#include "io/cloth_spec_json.h"
#include "io/vdb_writer.h"

namespace clothbake::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A 2 x 2 quad in the z = 0 plane, front +z.
constexpr const char* kQuadObj =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";

// The smallest valid scene: camera on +z looking at the quad.
json minimal_scene() {
  return json::parse(R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
    "lights": [{"type": "directional", "direction": [0, 0, -1]}],
    "objects": [{"mesh": "quad.obj", "cloth": {}}]
  })");
}

class SceneJson : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("clothbake_scene_test_" +
             std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(m_dir);
    write("quad.obj", kQuadObj);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = m_dir / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  // Loads the minimal scene changed by `edit`; returns "field | message" or "(no error)".
  std::string error_of(const std::function<void(json&)>& edit) {
    json scene = minimal_scene();
    edit(scene);
    return error_of_text(scene.dump(2));
  }
  std::string error_of_text(const std::string& text) {
    const std::string path = write("scene.json", text);
    try {
      (void)load_scene(path);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return e.field() + " | " + e.message();
    }
    return "(no error)";
  }
  fs::path m_dir;
};

TEST_F(SceneJson, ReadsEveryKey) {
  write("cloth.json", R"({"weave": {"pattern": "twill_2_1"}})");
  const std::string path = write("scene.json", R"({
    "name": "all", "description": "every key",
    "camera": {"position": [1, 2, 3], "look_at": [0, 0, -1], "up": [0, 0, 1], "fov_deg": 30,
               "fov_axis": "vertical", "resolution": [320, 200]},
    "lights": [{"type": "directional", "direction": [0, -3, -4], "color": [1, 0.5, 0.25],
                "intensity": 3},
               {"type": "point", "position": [4, 5, 6], "color": [0.2, 0.3, 0.4],
                "intensity": 10},
               {"type": "spot", "position": [0, 0, 4], "direction": [0, 0, -2],
                "spot_size_deg": 60, "spot_blend": 0.5, "axis_cosine": false, "intensity": 7},
               {"type": "area", "position": [1, 0, 3], "direction": [0, 0, -1],
                "x_axis": [2, 0, 1], "shape": "ellipse", "size": [2, 0.5], "intensity": 4},
               {"type": "area", "position": [1, 0, 3], "direction": [0, 0, -1],
                "x_axis": [0, 1, 0], "shape": "square", "size": 0.25}],
    "objects": [{"name": "cloth", "mesh": "quad.obj", "cloth": "cloth.json",
                 "repeats_per_uv": 20, "thickness_world": 0.02, "extinction_per_mm": 12.5,
                 "isotropic_albedo": [0.5, 0.6, 0.7]},
                {"mesh": "quad.obj", "cloth": {"crimp": 0.5}}],
    "background": [0.05, 0.05, 0.06],
    "render": {"spp": 16, "step_cells": 0.25, "fiber_model": "kajiya-kay", "fiber_samples": 100,
               "transmittance": "shadow-march", "shading": "isotropic", "cutoff": 0.01,
               "seed": 7}
  })");
  const Scene s = load_scene(path);
  EXPECT_EQ(s.camera.position_world, Imath::V3f(1, 2, 3));
  EXPECT_EQ(s.camera.look_at_world, Imath::V3f(0, 0, -1));
  EXPECT_EQ(s.camera.up_world, Imath::V3f(0, 0, 1));
  EXPECT_FLOAT_EQ(s.camera.fov_deg, 30.0f);
  EXPECT_EQ(s.camera.fov_axis, FovAxis::Vertical);
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 200);

  ASSERT_EQ(s.lights.size(), 5u);
  EXPECT_EQ(s.lights[0].type, LightType::Directional);
  // The file gives the direction the light travels; the struct the way back to it.
  EXPECT_FLOAT_EQ(s.lights[0].to_light_world.x, 0.0f);
  EXPECT_FLOAT_EQ(s.lights[0].to_light_world.y, 0.6f);
  EXPECT_FLOAT_EQ(s.lights[0].to_light_world.z, 0.8f);
  EXPECT_EQ(s.lights[0].color, Imath::V3f(1, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(s.lights[0].intensity, 3.0f);
  EXPECT_EQ(s.lights[1].type, LightType::Point);
  EXPECT_EQ(s.lights[1].position_world, Imath::V3f(4, 5, 6));
  EXPECT_FLOAT_EQ(s.lights[1].intensity, 10.0f);
  // A spot: Blender's size (full angle) and blend as Cycles' cosine and band.
  EXPECT_EQ(s.lights[2].type, LightType::Spot);
  EXPECT_EQ(s.lights[2].axis_world, Imath::V3f(0, 0, -1));
  EXPECT_FLOAT_EQ(s.lights[2].spot_cos_half_angle, std::cos(30.0f * 3.14159265f / 180.0f));
  EXPECT_FLOAT_EQ(s.lights[2].spot_smooth, (1.0f - std::cos(30.0f * 3.14159265f / 180.0f)) * 0.5f);
  EXPECT_FLOAT_EQ(s.lights[2].intensity, 7.0f);
  EXPECT_FALSE(s.lights[2].spot_axis_cosine);
  // An area light: the x axis made orthogonal to the normal, the sides as given.
  EXPECT_EQ(s.lights[3].type, LightType::Area);
  EXPECT_EQ(s.lights[3].area_shape, AreaShape::Ellipse);
  EXPECT_EQ(s.lights[3].side_world, Imath::V3f(1, 0, 0));
  EXPECT_FLOAT_EQ(s.lights[3].area_width, 2.0f);
  EXPECT_FLOAT_EQ(s.lights[3].area_height, 0.5f);
  EXPECT_EQ(s.lights[4].area_shape, AreaShape::Rectangle);
  EXPECT_FLOAT_EQ(s.lights[4].area_width, 0.25f);
  EXPECT_FLOAT_EQ(s.lights[4].area_height, 0.25f);
  EXPECT_FLOAT_EQ(s.lights[4].intensity, 1.0f);

  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].name, "cloth");
  EXPECT_EQ(s.objects[0].cloth.pattern, "twill_2_1");
  EXPECT_EQ(s.objects[0].mesh.quads.size(), 1u);
  EXPECT_FLOAT_EQ(s.objects[0].repeats_per_uv, 20.0f);
  EXPECT_FLOAT_EQ(s.objects[0].thickness_world, 0.02f);
  EXPECT_FLOAT_EQ(s.objects[0].extinction_per_mm, 12.5f);
  EXPECT_EQ(s.objects[0].isotropic_albedo, Imath::V3f(0.5f, 0.6f, 0.7f));
  EXPECT_EQ(s.objects[1].name, "objects[1]");
  EXPECT_FLOAT_EQ(s.objects[1].cloth.crimp, 0.5f);

  EXPECT_EQ(s.background, Imath::V3f(0.05f, 0.05f, 0.06f));
  EXPECT_EQ(s.settings.spp, 16);
  EXPECT_FLOAT_EQ(s.settings.step_cells, 0.25f);
  EXPECT_EQ(s.settings.fiber_model, FiberModelKind::KajiyaKay);
  EXPECT_EQ(s.settings.fiber_samples, 100);
  EXPECT_EQ(s.settings.transmittance, TransmittanceMode::ShadowMarch);
  EXPECT_EQ(s.settings.shading, ShadingMode::Isotropic);
  EXPECT_FLOAT_EQ(s.settings.cutoff, 0.01f);
  EXPECT_EQ(s.settings.seed, 7u);
}

TEST_F(SceneJson, AbsentKeysKeepTheStructDefaults) {
  const Scene s = load_scene(write("scene.json", minimal_scene().dump()));
  const PinholeCamera camera;
  const RenderSettings render;
  const ClothObject object;
  const Light light;
  const ClothSpec cloth;
  EXPECT_EQ(s.camera.up_world, camera.up_world);
  EXPECT_FLOAT_EQ(s.camera.fov_deg, camera.fov_deg);
  EXPECT_EQ(s.camera.fov_axis, camera.fov_axis);
  EXPECT_EQ(s.camera.width, camera.width);
  EXPECT_EQ(s.camera.height, camera.height);
  EXPECT_EQ(s.lights[0].color, light.color);
  EXPECT_FLOAT_EQ(s.lights[0].intensity, light.intensity);
  EXPECT_FLOAT_EQ(s.objects[0].repeats_per_uv, object.repeats_per_uv);
  EXPECT_FLOAT_EQ(s.objects[0].thickness_world, object.thickness_world);
  EXPECT_FLOAT_EQ(s.objects[0].extinction_per_mm, object.extinction_per_mm);
  EXPECT_EQ(s.objects[0].isotropic_albedo, object.isotropic_albedo);
  EXPECT_EQ(s.objects[0].cloth.pattern, cloth.pattern);
  EXPECT_FLOAT_EQ(s.objects[0].cloth.warp.width_mm, cloth.warp.width_mm);
  EXPECT_EQ(s.background, Imath::V3f(0, 0, 0));
  EXPECT_EQ(s.settings.spp, render.spp);
  EXPECT_FLOAT_EQ(s.settings.step_cells, render.step_cells);
  EXPECT_EQ(s.settings.fiber_model, render.fiber_model);
  EXPECT_EQ(s.settings.fiber_samples, render.fiber_samples);
  EXPECT_EQ(s.settings.transmittance, render.transmittance);
  EXPECT_EQ(s.settings.shading, render.shading);
  EXPECT_FLOAT_EQ(s.settings.cutoff, render.cutoff);
  EXPECT_EQ(s.settings.seed, render.seed);
}

TEST_F(SceneJson, PathsAreRelativeToTheSceneFile) {
  write("scenes/meshes/m.obj", kQuadObj);
  write("scenes/specs/c.json", R"({"crimp": 0.25})");
  json scene = minimal_scene();
  scene["objects"][0]["mesh"] = "meshes/m.obj";
  scene["objects"][0]["cloth"] = "specs/c.json";
  const Scene s = load_scene(write("scenes/scene.json", scene.dump()));
  EXPECT_EQ(s.objects[0].mesh.quads.size(), 1u);
  EXPECT_FLOAT_EQ(s.objects[0].cloth.crimp, 0.25f);
  // load_cloth_spec still reads a scene's first cloth the same way.
  EXPECT_FLOAT_EQ(load_cloth_spec((m_dir / "scenes/scene.json").string()).crimp, 0.25f);
}

TEST_F(SceneJson, ErrorsNameTheField) {
  EXPECT_EQ(error_of([](json& s) { s.erase("camera"); }), "camera | missing");
  EXPECT_EQ(error_of([](json& s) { s["camra"] = json::object(); }).substr(0, 20),
            "camra | unknown key;");
  EXPECT_EQ(error_of([](json& s) { s["camera"]["fov"] = 40; }).substr(0, 25),
            "camera.fov | unknown key;");
  EXPECT_EQ(error_of([](json& s) { s["camera"]["fov_deg"] = "wide"; }),
            "camera.fov_deg | expected a number, got a string");
  EXPECT_EQ(error_of([](json& s) { s["camera"]["fov_deg"] = 180; }),
            "camera.fov_deg | must be in (0, 180) degrees, got 180");
  EXPECT_EQ(error_of([](json& s) { s["camera"]["fov_deg"] = 0; }),
            "camera.fov_deg | must be in (0, 180) degrees, got 0");
  // An integer above INT64_MAX is out of range, not wrapped to -1.
  EXPECT_EQ(error_of([](json& s) { s["render"]["spp"] = 18446744073709551615ull; }),
            "render.spp | integer out of range: 18446744073709551615");
  EXPECT_EQ(error_of([](json& s) { s["camera"]["fov_axis"] = "diagonal"; }),
            "camera.fov_axis | unknown value 'diagonal'; expected one of: horizontal, vertical");
  EXPECT_EQ(error_of([](json& s) {
              s["camera"]["resolution"] = {0, 266};
            }),
            "camera.resolution[0] | must be in [1, 16384] pixels, got 0");
  EXPECT_EQ(error_of([](json& s) {
              s["camera"]["resolution"] = {426, 16385};
            }),
            "camera.resolution[1] | must be in [1, 16384] pixels, got 16385");
  EXPECT_EQ(error_of([](json& s) {
              s["camera"]["resolution"] = {426, 26.5};
            }),
            "camera.resolution[1] | expected an integer, got a number with a fraction");
  EXPECT_EQ(error_of([](json& s) { s["camera"]["resolution"] = {426}; }),
            "camera.resolution | expected [width, height] in pixels, got an array of 1");
  EXPECT_EQ(error_of([](json& s) {
              s["camera"]["position"] = {0, 0, 0};
            }),
            "camera.look_at | equals camera.position [0, 0, 0]; the camera needs a direction to "
            "look in");
  EXPECT_EQ(error_of([](json& s) {
              s["camera"]["up"] = {0, 0, -2};
            }).substr(0, 42),
            "camera.up | is parallel to the view direct");
  EXPECT_EQ(error_of([](json& s) {
              s["camera"]["up"] = {0, 0, 0};
            }),
            "camera.up | must not be the zero vector");

  EXPECT_EQ(error_of([](json& s) { s.erase("lights"); }),
            "lights | missing; give at least one light");
  EXPECT_EQ(error_of([](json& s) { s["lights"] = json::array(); }),
            "lights | expected a non-empty array of lights, got an array of 0");
  EXPECT_EQ(error_of([](json& s) { s["lights"][0]["type"] = "laser"; }),
            "lights[0].type | unknown light type 'laser'; expected one of: directional, point, "
            "spot, area");
  EXPECT_EQ(error_of([](json& s) { s["lights"][0].erase("type"); }),
            "lights[0].type | missing; expected one of: directional, point, spot, area");
  EXPECT_EQ(error_of([](json& s) {
              s["lights"][0]["direction"] = {0, 0, 0};
            }).substr(0, 50),
            "lights[0].direction | must not be the zero vector ");
  EXPECT_EQ(error_of([](json& s) {
              s["lights"][0]["position"] = {0, 0, 1};
            }).substr(0, 33),
            "lights[0].position | unknown key;");
  EXPECT_EQ(error_of([](json& s) { s["lights"][0]["intensity"] = -1; }),
            "lights[0].intensity | must be >= 0, got -1");
  EXPECT_EQ(error_of([](json& s) {
              s["lights"][0]["color"] = {1, -0.5, 1};
            }),
            "lights[0].color | must be >= 0 in every channel, got [1, -0.5, 1]");
  EXPECT_EQ(error_of([](json& s) {
              s["lights"][1] = {{"type", "point"}, {"color", {1, 1, 1}}};
            }),
            "lights[1].position | missing (where the point light is)");

  EXPECT_EQ(error_of([](json& s) {
              s["background"] = {0, 0};
            }),
            "background | expected an array of three numbers, got an array of 2");
  EXPECT_EQ(error_of([](json& s) { s["render"]["fiber_model"] = "phong"; }),
            "render.fiber_model | unknown value 'phong'; expected one of: ellipsoid, table, "
            "kajiya-kay");
  EXPECT_EQ(error_of([](json& s) { s["render"]["transmittance"] = "exact"; }).substr(0, 42),
            "render.transmittance | unknown value 'exac");
  EXPECT_EQ(error_of([](json& s) { s["render"]["shading"] = 1; }),
            "render.shading | expected a string, got a number");
  EXPECT_EQ(error_of([](json& s) { s["render"]["spp"] = 0; }),
            "render.spp | must be in [1, 65536], got 0");
  EXPECT_EQ(error_of([](json& s) { s["render"]["spp"] = 65537; }),
            "render.spp | must be in [1, 65536], got 65537");
  EXPECT_EQ(error_of([](json& s) { s["render"]["step_cells"] = 0; }),
            "render.step_cells | must be in (0, 16] cells, got 0");
  EXPECT_EQ(error_of([](json& s) { s["render"]["step_cells"] = 16.5; }),
            "render.step_cells | must be in (0, 16] cells, got 16.5");
  EXPECT_EQ(error_of([](json& s) { s["render"]["fiber_samples"] = 0; }),
            "render.fiber_samples | must be in [1, 65536], got 0");
  EXPECT_EQ(error_of([](json& s) { s["render"]["cutoff"] = 1; }),
            "render.cutoff | must be in [0, 1), got 1");
  EXPECT_EQ(error_of([](json& s) { s["render"]["seed"] = -1; }),
            "render.seed | expected a non-negative integer, got a number");

  EXPECT_EQ(error_of([](json& s) { s.erase("objects"); }),
            "objects | missing; give at least one cloth object");
  EXPECT_EQ(error_of([](json& s) { s["objects"] = json::object(); }),
            "objects | expected a non-empty array of cloth objects, got an object");
  EXPECT_EQ(error_of([](json& s) { s["objects"][1] = 3; }),
            "objects[1] | expected an object, got a number");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["thickness_world"] = 0; }),
            "objects[0].thickness_world | must be greater than 0, got 0");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["repeats_per_uv"] = -2; }),
            "objects[0].repeats_per_uv | must be greater than 0, got -2");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["extinction_per_mm"] = -1; }),
            "objects[0].extinction_per_mm | must be >= 0, got -1");
  EXPECT_EQ(error_of([](json& s) {
              s["objects"][0]["isotropic_albedo"] = {0.5, 1.5, 0.5};
            }),
            "objects[0].isotropic_albedo | must be in [0, 1] in every channel, got [0.5, 1.5, "
            "0.5]");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0].erase("mesh"); }).substr(0, 26),
            "objects[0].mesh | missing ");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0].erase("cloth"); }).substr(0, 27),
            "objects[0].cloth | missing ");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["cloth"] = 5; }),
            "objects[0].cloth | expected a cloth spec object or the path of a cloth spec file, "
            "got a number");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["cloth"]["crimp"] = 1e300; }),
            "objects[0].cloth.crimp | must be a finite number");
}

TEST_F(SceneJson, InlineClothErrorsNameTheScenePath) {
  EXPECT_EQ(error_of([](json& s) {
              s["objects"][0]["cloth"]["warp"] = {{"width_mm", -0.2}};
            }).substr(0, 49),
            "objects[0].cloth.warp.width_mm | must be greater ");
  EXPECT_EQ(error_of([](json& s) {
              s["objects"][0]["cloth"]["weave"] = {{"pattern", "tartan"}};
            }).substr(0, 50),
            "objects[0].cloth.weave.pattern | unknown weave 'ta");
}

TEST_F(SceneJson, ReferencedFilesAreNamedWithTheSceneField) {
  const std::string spec = write("bad_cloth.json", R"({"crimp": "high"})");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["cloth"] = "bad_cloth.json"; }),
            "objects[0].cloth | " + spec + ": crimp: expected a number, got a string");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["cloth"] = "none.json"; }),
            "objects[0].cloth | " + (m_dir / "none.json").string() +
                ": cannot open file (missing or unreadable): No such file or directory");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["mesh"] = "missing.obj"; }),
            "objects[0].mesh | mesh file not found: " + (m_dir / "missing.obj").string());
  const std::string tri = write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n");
  EXPECT_EQ(error_of([](json& s) { s["objects"][0]["mesh"] = "tri.obj"; }),
            "objects[0].mesh | " + tri +
                ": line 5: face has 3 corners; clothbake needs quads (4 corners)");
}

TEST_F(SceneJson, VolumeReplacesTheGeneratedTexture) {
  // A VDB beside the scene: the object's texture, the spec optional.
  ClothSpec spec;
  spec.resolution = {8, 8, 4, 1};
  fs::create_directories(m_dir / "tex");
  write_volume_vdb((m_dir / "tex" / "volume.vdb").string(),
                   generate_volume(spec, uint64_t(1) << 30), "test");
  const std::string path = write("scene.json", R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
    "lights": [{"type": "directional", "direction": [0, 0, -1]}],
    "objects": [{"mesh": "quad.obj", "volume": "tex/volume.vdb"},
                {"mesh": "quad.obj", "volume": "tex/volume.vdb",
                 "cloth": {"shading": {"fiber_aspect": 3}}},
                {"mesh": "quad.obj", "cloth": {}}]
  })");
  const Scene s = load_scene(path);
  ASSERT_TRUE(s.objects[0].volume && s.objects[1].volume);
  EXPECT_EQ(s.objects[0].volume->nx(), 8);
  EXPECT_EQ(s.objects[0].volume->nz(), 4);
  EXPECT_FLOAT_EQ(s.objects[0].cloth.shading.fiber_aspect, ClothSpec().shading.fiber_aspect);
  EXPECT_FLOAT_EQ(s.objects[1].cloth.shading.fiber_aspect, 3.0f);
  EXPECT_FALSE(s.objects[2].volume);

  EXPECT_EQ(error_of([](json& j) { j["objects"][0].erase("cloth"); }),
            "objects[0].cloth | missing (an inline cloth spec or the path of a cloth spec file; "
            "or give a \"volume\")");
  EXPECT_EQ(error_of([](json& j) { j["objects"][0]["volume"] = ""; }),
            "objects[0].volume | is empty; expected the path of a VDB file");
  EXPECT_EQ(error_of([](json& j) { j["objects"][0]["volume"] = "none.vdb"; }),
            "objects[0].volume | " + (m_dir / "none.vdb").string() +
                ": cannot open file (missing or unreadable)");
}

TEST_F(SceneJson, RefusesACameraInsideTheClothVolume) {
  // The quad's volume lies behind its front (+z) face, 0.01 deep.
  auto at = [](float x, float z) {
    return [x, z](json& s) {
      s["camera"]["position"] = {x, 0.25, z};
      s["camera"]["look_at"] = {0, 0, 10};
    };
  };
  EXPECT_EQ(error_of(at(0.0f, -0.005f)),
            "camera | position is inside the cloth volume of objects[0] (distance 0.005 < "
            "thickness_world 0.01)");
  EXPECT_EQ(error_of(at(0.5f, 0.0f)).substr(0, 52),
            "camera | position is inside the cloth volume of obje");
  EXPECT_EQ(error_of(at(0.0f, 0.005f)), "(no error)");   // in front of the face
  EXPECT_EQ(error_of(at(0.0f, -0.02f)), "(no error)");   // behind the volume
  EXPECT_EQ(error_of(at(3.0f, -0.005f)), "(no error)");  // beside the quad
  // Thicker cloth swallows the same camera.
  EXPECT_NE(error_of([&](json& s) {
              at(0.0f, -0.02f)(s);
              s["objects"][0]["thickness_world"] = 0.05;
            }),
            "(no error)");
}

TEST_F(SceneJson, RefusesMalformedAndOverflowingJson) {
  EXPECT_EQ(error_of_text("{\"camera\": {},\n}").substr(0, 38),
            " | malformed JSON at line 2, column 1 ");
  EXPECT_EQ(error_of_text(R"({"background": [0, 1e999, 0]})").substr(0, 36),
            " | invalid JSON: number overflow par");
  EXPECT_EQ(error_of_text("[1, 2]"), " | expected an object, got an array");
}

TEST_F(SceneJson, LoadsTheTestScenes) {
  const Scene paper = load_scene(CLOTHBAKE_SOURCE_DIR "/testscenes/paper/scene.json");
  EXPECT_EQ(paper.camera.width, 426);
  EXPECT_EQ(paper.camera.height, 266);
  ASSERT_EQ(paper.objects.size(), 1u);
  EXPECT_EQ(paper.objects[0].mesh.quads.size(), 64u);
  EXPECT_EQ(paper.objects[0].cloth.pattern, "plain");
  EXPECT_GE(paper.lights.size(), 2u);
  EXPECT_EQ(paper.settings.fiber_model, FiberModelKind::Table);
  EXPECT_EQ(paper.settings.transmittance, TransmittanceMode::ShadowMarch);
  // load_cloth_spec of the scene gives the scene's cloth file.
  const ClothSpec from_scene = load_cloth_spec(CLOTHBAKE_SOURCE_DIR "/testscenes/paper/scene.json");
  EXPECT_FLOAT_EQ(from_scene.warp.spacing_mm, paper.objects[0].cloth.warp.spacing_mm);

  const Scene slab = load_scene(CLOTHBAKE_SOURCE_DIR "/testscenes/slab/scene.json");
  ASSERT_EQ(slab.objects.size(), 1u);
  EXPECT_EQ(slab.objects[0].mesh.quads.size(), 1u);
  EXPECT_EQ(slab.settings.shading, ShadingMode::Isotropic);
  EXPECT_EQ(slab.objects[0].cloth.pattern, k_uniform_pattern);
  ASSERT_EQ(slab.lights.size(), 1u);
  // The light comes from 45 degrees off the slab's normal.
  EXPECT_NEAR(slab.lights[0].to_light_world.y, std::sqrt(0.5f), 1e-6f);
}

}  // namespace
}  // namespace clothbake::io
