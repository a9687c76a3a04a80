#include "io/obj_reader.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace clothbake::io {
namespace {

namespace fs = std::filesystem;

// One quad in the z = 0 plane, front (+z) counter-clockwise, UVs [0,1]^2.
constexpr const char* kQuad =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";

class ObjReader : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir =
        fs::temp_directory_path() /
        ("clothbake_obj_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  std::string write(const std::string& text) {
    const fs::path p = m_dir / "mesh.obj";
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  // Reads `text` and returns "field | message", or "(no error)".
  std::string error_of(const std::string& text) {
    const std::string path = write(text);
    try {
      (void)read_obj_quads(path);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return e.field() + " | " + e.message();
    }
    return "(no error)";
  }
  fs::path m_dir;
};

TEST_F(ObjReader, ReadsAQuadWithUvs) {
  const QuadMesh m = read_obj_quads(write(std::string(kQuad) + "f 1/1 2/2 3/3 4/4\n"));
  ASSERT_EQ(m.quads.size(), 1u);
  ASSERT_EQ(m.positions_world.size(), 4u);
  ASSERT_EQ(m.uvs.size(), 4u);
  EXPECT_EQ(m.quads[0].position, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.quads[0].uv, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.positions_world[2], Imath::V3f(1, 1, 0));
  EXPECT_EQ(m.uvs[3], Imath::V2f(0, 1));
}

TEST_F(ObjReader, AcceptsNormalsNegativeIndicesAndIgnoredStatements) {
  const QuadMesh m =
      read_obj_quads(write("# exported\r\nmtllib cloth.mtl\r\no Cloth\r\n" + std::string(kQuad) +
                           "vn 0 0 1\r\ng part\r\nusemtl red\r\ns off\r\n"
                           "f 1/4/1 2/3/1 3/2/1 4/1/1   # a comment\r\n"
                           "f -4/-4 -3/-3 -2/-2 -1/-1\r\n"));
  ASSERT_EQ(m.quads.size(), 2u);
  EXPECT_EQ(m.quads[0].uv, (std::array<int, 4>{3, 2, 1, 0}));
  EXPECT_EQ(m.quads[1].position, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.quads[1].uv, (std::array<int, 4>{0, 1, 2, 3}));
}

TEST_F(ObjReader, ErrorsNameTheLine) {
  const std::string q = kQuad;  // lines 1-8
  EXPECT_EQ(error_of(q + "f 1/1 2/2 3/3\n"),
            "line 9 | face has 3 corners; clothbake needs quads (4 corners)");
  EXPECT_EQ(error_of(q + "v 0 2 0\nf 1/1 2/2 3/3 5/4 4/4\n"),
            "line 10 | face has 5 corners; clothbake needs quads (4 corners)");
  EXPECT_EQ(error_of(q + "f 1//1 2//2 3//3 4//4\n").substr(0, 57),
            "line 9 | face corner 1 ('1//1') has no texture coordinate");
  EXPECT_EQ(error_of(q + "f 1/1 2/2 3 4/4\n").substr(0, 54),
            "line 9 | face corner 3 ('3') has no texture coordinate");
  EXPECT_EQ(error_of("v 0 0 zero\n"), "line 1 | malformed number 'zero' in vertex position");
  EXPECT_EQ(error_of("v 0 0 1.5x\n"), "line 1 | malformed number '1.5x' in vertex position");
  EXPECT_EQ(error_of("v 0 1e999 0\n"),
            "line 1 | malformed number '1e999' in vertex position (out of range)");
  EXPECT_EQ(error_of("v 0 nan 0\n"), "line 1 | non-finite number 'nan' in vertex position");
  EXPECT_EQ(error_of("v 0 0 0\nvt inf 0\n"),
            "line 2 | non-finite number 'inf' in texture coordinate");
  EXPECT_EQ(error_of("v 0 0\n"), "line 1 | 'v' needs three coordinates x y z");
  EXPECT_EQ(error_of("vt 0\n"), "line 1 | 'vt' needs two coordinates u v");
  EXPECT_EQ(error_of(q + "f 1/1 2/2 3/3 5/4\n"),
            "line 9 | vertex index 5 of corner 4 is out of range (4 vertices)");
  EXPECT_EQ(error_of(q + "f 1/1 2/2 3/3 -5/4\n"),
            "line 9 | vertex index -5 of corner 4 is out of range (4 vertices)");
  EXPECT_EQ(error_of(q + "f 1/1 2/9 3/3 4/4\n"),
            "line 9 | texture coordinate index 9 of corner 2 is out of range (4 texture "
            "coordinates)");
  EXPECT_EQ(error_of(q + "f 0/1 2/2 3/3 4/4\n").substr(0, 31), "line 9 | malformed index '0' in");
  EXPECT_EQ(error_of(q + "curv 0 1 1 2\n").substr(0, 44),
            "line 9 | unsupported OBJ statement 'curv' (c");
}

TEST_F(ObjReader, RefusesAMissingFileAndAnEmptyMesh) {
  try {
    (void)read_obj_quads((m_dir / "nope.obj").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (m_dir / "nope.obj").string());
    EXPECT_EQ(e.message(), "cannot open file (missing or unreadable): No such file or directory");
  }
  EXPECT_EQ(error_of(kQuad), " | the mesh has no faces; clothbake needs at least one quad");
  EXPECT_EQ(error_of(""), " | the mesh has no faces; clothbake needs at least one quad");
}

TEST_F(ObjReader, RefusesZeroAreaQuads) {
  // Corners 3 and 4 coincide with 2 and 1: a sliver of no area.
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "f 1/1 2/2 3/3 4/4\nf 1/1 2/2 2/3 1/4\n")
                .substr(0, 30),
            "line 10 | quad has zero area (");
  // All four corners on one line.
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\n"
                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n")
                .substr(0, 29),
            "line 9 | quad has zero area (");
  // A triangle written as a quad: area, but a collapsed edge.
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 3/4\n"),
            "line 9 | corners 3 and 4 are the same point; a quad needs four distinct corners");
  // UVs that collapse to a line cannot carry the weave.
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                     "vt 0 0\nvt 1 0\nf 1/1 2/2 3/2 4/1\n"),
            "line 7 | quad's texture coordinates have zero area; the weave cannot be mapped onto "
            "it");
}

TEST_F(ObjReader, ZeroAreaIsRelativeToTheMeshSize) {
  // A tiny but healthy quad (1e-5 units) passes; the test is scale-free.
  EXPECT_EQ(error_of("v 0 0 0\nv 1e-5 0 0\nv 1e-5 1e-5 0\nv 0 1e-5 0\n"
                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n"),
            "(no error)");
  // A sliver 1e-7 of the mesh size across next to a unit quad has an area
  // of 1e-7, far above 1e-12 of the squared diagonal: still accepted.
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 1e-7 0\nv 0 1e-7 0\n"
                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "f 1/1 2/2 3/3 4/4\nf 1/1 2/2 5/3 6/4\n"),
            "(no error)");
}

TEST_F(ObjReader, ReadsThePaperCloth) {
  const QuadMesh m = read_obj_quads(CLOTHBAKE_SOURCE_DIR "/testscenes/paper/cloth.obj");
  EXPECT_EQ(m.quads.size(), 64u);
  EXPECT_EQ(m.positions_world.size(), 81u);
  EXPECT_EQ(m.uvs.size(), 81u);
  for (const Imath::V2f& uv : m.uvs) {
    EXPECT_GE(uv.x, 0.0f);
    EXPECT_LE(uv.x, 1.0f);
    EXPECT_GE(uv.y, 0.0f);
    EXPECT_LE(uv.y, 1.0f);
  }
}

}  // namespace
}  // namespace clothbake::io
