#include "io/vdb_reader.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include "core/util/error.h"
#include "core/texture/volume_generator.h"
#include "io/vdb_writer.h"

namespace clothbake::io {
namespace {

namespace fs = std::filesystem;
constexpr uint64_t k_budget = uint64_t(1) << 30;

/// A small generated texture written by clothbake's writer, and variants of
/// its file with one thing broken.
class VdbReader : public ::testing::Test {
 protected:
  void SetUp() override {
    openvdb::initialize();
    m_dir = fs::temp_directory_path() /
            ("clothbake_vdb_reader_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(m_dir);
    ClothSpec spec;
    spec.resolution = {16, 16, 6, 1};
    m_volume = generate_volume(spec, k_budget);
    m_good = (m_dir / "good.vdb").string();
    write_volume_vdb(m_good, m_volume, "test");
  }
  void TearDown() override { fs::remove_all(m_dir); }

  /// Writes the good file's grids, after `edit`, as NAME.vdb; returns its path.
  std::string variant(const std::string& name,
                      const std::function<void(openvdb::GridPtrVec&)>& edit) {
    openvdb::io::File in(m_good);
    in.open();
    const openvdb::GridPtrVecPtr read = in.getGrids();
    openvdb::GridPtrVec grids(read->begin(), read->end());
    const openvdb::MetaMap::Ptr meta = in.getMetadata();
    in.close();
    edit(grids);
    const std::string path = (m_dir / (name + ".vdb")).string();
    openvdb::io::File out(path);
    out.write(grids, *meta);
    out.close();
    return path;
  }

  static openvdb::GridBase::Ptr& grid(openvdb::GridPtrVec& grids, const std::string& name) {
    for (auto& g : grids)
      if (g->getName() == name) return g;
    throw std::runtime_error("no grid " + name);
  }
  static openvdb::FloatGrid& float_grid(openvdb::GridPtrVec& grids, const std::string& name) {
    return *openvdb::gridPtrCast<openvdb::FloatGrid>(grid(grids, name));
  }
  static openvdb::Vec3SGrid& vec_grid(openvdb::GridPtrVec& grids, const std::string& name) {
    return *openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid(grids, name));
  }

  /// The message read_volume_vdb throws for `path`, or "" when it accepts it.
  static std::string error_of(const std::string& path, uint64_t budget = k_budget) {
    try {
      read_volume_vdb(path, budget);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  /// A fibre cell (density > 0) of the generated texture.
  openvdb::Coord fibre_cell() const {
    for (int k = 0; k < m_volume.nz(); ++k)
      for (int j = 0; j < m_volume.ny(); ++j)
        for (int i = 0; i < m_volume.nx(); ++i)
          if (m_volume.at(i, j, k).density > 0.5f) return openvdb::Coord(i, j, k);
    throw std::runtime_error("no fibre cell");
  }

  fs::path m_dir;
  VolumeTexture m_volume;
  std::string m_good;
};

TEST_F(VdbReader, RoundTripGivesTheSameCellsBitForBit) {
  const VolumeTexture read = read_volume_vdb(m_good, k_budget);
  ASSERT_EQ(read.nx(), m_volume.nx());
  ASSERT_EQ(read.ny(), m_volume.ny());
  ASSERT_EQ(read.nz(), m_volume.nz());
  EXPECT_EQ(read.size_mm(), m_volume.size_mm());
  EXPECT_EQ(read.cell_size_mm(), m_volume.cell_size_mm());
  int fibre = 0;
  for (size_t n = 0; n < read.cell_count(); ++n) {
    const Cell &a = read.cells()[n], &b = m_volume.cells()[n];
    ASSERT_EQ(a.density, b.density) << n;
    ASSERT_EQ(a.tangent, b.tangent) << n;
    ASSERT_EQ(a.diffuse, b.diffuse) << n;
    ASSERT_EQ(a.specular, b.specular) << n;
    ASSERT_EQ(a.exponent, b.exponent) << n;
    EXPECT_EQ(a.family, YarnFamily::None);  // not stored in the VDB
    fibre += b.density > 0.0f;
  }
  EXPECT_GT(fibre, 0);
}

TEST_F(VdbReader, MissingFile) {
  const std::string path = (m_dir / "none.vdb").string();
  EXPECT_EQ(error_of(path), path + ": cannot open file (missing or unreadable)");
}

TEST_F(VdbReader, NotAVdbFile) {
  const std::string path = (m_dir / "text.vdb").string();
  std::ofstream(path) << "{\"this\": \"is JSON\"}\n";
  EXPECT_EQ(error_of(path), path + ": not a readable OpenVDB file (IoError: not a VDB file)");
}

TEST_F(VdbReader, EachMissingGridIsNamed) {
  for (const char* name : k_vdb_grid_names) {
    const std::string path = variant(std::string("no_") + name, [&](openvdb::GridPtrVec& grids) {
      std::erase_if(grids, [&](const auto& g) { return g->getName() == name; });
    });
    EXPECT_EQ(error_of(path),
              path + ": " + name +
                  ": grid missing; a clothbake volume needs the grids density (float), tangent "
                  "(vec3s), diffuse (vec3s), specular (float) and exponent (float)");
  }
}

TEST_F(VdbReader, WrongGridTypes) {
  const std::string a = variant("double_density", [](openvdb::GridPtrVec& grids) {
    auto& g = grid(grids, "density");
    auto d = openvdb::DoubleGrid::create(0.0);
    d->setName("density");
    d->setTransform(g->transform().copy());
    d->tree().setValue(openvdb::Coord(0, 0, 0), 0.5);
    g = d;
  });
  EXPECT_EQ(error_of(a), a + ": density: grid has values of type double; expected float");
  const std::string b = variant("float_tangent", [](openvdb::GridPtrVec& grids) {
    auto& g = grid(grids, "tangent");
    auto f = openvdb::FloatGrid::create(0.0f);
    f->setName("tangent");
    f->setTransform(g->transform().copy());
    f->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
    g = f;
  });
  EXPECT_EQ(error_of(b), b + ": tangent: grid has values of type float; expected vec3s");
}

TEST_F(VdbReader, TransformsMustAgree) {
  const std::string path = variant("diffuse_scaled", [](openvdb::GridPtrVec& grids) {
    grid(grids, "diffuse")->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
  });
  EXPECT_EQ(error_of(path), path +
                                ": diffuse: transform (voxel size [0.5, 0.5, 0.5] mm) differs from "
                                "the density grid's (voxel size [0.0625, 0.0625, 0.06] mm); all "
                                "five grids must share one transform");
}

TEST_F(VdbReader, VaryingVoxelSizeIsRefused) {
  const std::string path = variant("frustum", [](openvdb::GridPtrVec& grids) {
    const auto frustum = openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(16, 16, 6)), 0.5, 1.0, 0.1);
    for (auto& g : grids) g->setTransform(frustum);
  });
  EXPECT_EQ(error_of(path),
            path +
                ": density: transform is not linear (NonlinearFrustumMap): the voxel size "
                "varies across the grid; clothbake needs one voxel size for the whole grid");
}

TEST_F(VdbReader, RotatedGridIsRefused) {
  const std::string path = variant("rotated", [](openvdb::GridPtrVec& grids) {
    auto xform = openvdb::math::Transform::createLinearTransform(0.1);
    xform->postRotate(0.3, openvdb::math::Z_AXIS);
    for (auto& g : grids) g->setTransform(xform);
  });
  EXPECT_EQ(error_of(path), path +
                                ": density: transform rotates or shears the grid; clothbake needs "
                                "an axis-aligned grid (a scale and an offset)");
}

TEST_F(VdbReader, ActiveBoundingBoxesMustAgree) {
  const std::string path = variant("specular_wider", [](openvdb::GridPtrVec& grids) {
    float_grid(grids, "specular").tree().setValue(openvdb::Coord(20, 0, 0), 0.1f);
  });
  EXPECT_EQ(error_of(path),
            path +
                ": specular: active voxels span (0, 0, 0) to (20, 15, 5) (index space), the "
                "density grid's span (0, 0, 0) to (15, 15, 5); all five grids must cover the "
                "same voxels");
}

TEST_F(VdbReader, EmptyGridIsRefused) {
  const std::string path = variant("empty_exponent", [](openvdb::GridPtrVec& grids) {
    auto& g = grid(grids, "exponent");
    auto e = openvdb::FloatGrid::create(0.0f);
    e->setName("exponent");
    e->setTransform(g->transform().copy());
    g = e;
  });
  EXPECT_EQ(error_of(path), path + ": exponent: grid is empty (no active voxels)");
}

TEST_F(VdbReader, DensityOutsideZeroOne) {
  const std::string path = variant("density_high", [](openvdb::GridPtrVec& grids) {
    float_grid(grids, "density").tree().setValue(openvdb::Coord(1, 2, 3), 1.5f);
  });
  EXPECT_EQ(error_of(path), path + ": density: voxel (1, 2, 3) is 1.5; density must be in [0, 1]");
  const std::string low = variant("density_low", [](openvdb::GridPtrVec& grids) {
    float_grid(grids, "density").tree().setValue(openvdb::Coord(0, 0, 0), -0.25f);
  });
  EXPECT_EQ(error_of(low), low + ": density: voxel (0, 0, 0) is -0.25; density must be in [0, 1]");
}

TEST_F(VdbReader, NonFiniteValues) {
  const std::string nan = variant("specular_nan", [](openvdb::GridPtrVec& grids) {
    float_grid(grids, "specular")
        .tree()
        .setValue(openvdb::Coord(4, 5, 1), std::numeric_limits<float>::quiet_NaN());
  });
  EXPECT_EQ(error_of(nan),
            nan + ": specular: voxel (4, 5, 1) is not a finite number; values must be finite");
  const std::string inf = variant("diffuse_inf", [](openvdb::GridPtrVec& grids) {
    vec_grid(grids, "diffuse")
        .tree()
        .setValue(openvdb::Coord(0, 1, 2),
                  openvdb::Vec3s(0.5f, std::numeric_limits<float>::infinity(), 0.5f));
  });
  EXPECT_EQ(error_of(inf),
            inf + ": diffuse: voxel (0, 1, 2) is not a finite number; values must be finite");
}

TEST_F(VdbReader, NegativeCoefficients) {
  const std::string path = variant("exponent_negative", [](openvdb::GridPtrVec& grids) {
    float_grid(grids, "exponent").tree().setValue(openvdb::Coord(2, 2, 2), -3.0f);
  });
  EXPECT_EQ(error_of(path),
            path + ": exponent: voxel (2, 2, 2) is -3; the Phong exponent must be >= 0");
}

TEST_F(VdbReader, TangentsWhereDensityIsPositive) {
  const openvdb::Coord c = fibre_cell();
  const float rho = m_volume.at(c.x(), c.y(), c.z()).density;
  char rho_text[32];
  std::snprintf(rho_text, sizeof rho_text, "%g", rho);
  const std::string where = "voxel (" + std::to_string(c.x()) + ", " + std::to_string(c.y()) +
                            ", " + std::to_string(c.z()) + ")";

  const std::string zero = variant("tangent_zero", [&](openvdb::GridPtrVec& grids) {
    vec_grid(grids, "tangent").tree().setValue(c, openvdb::Vec3s(0, 0, 0));
  });
  EXPECT_EQ(error_of(zero), zero + ": tangent: " + where + " is zero where density is " + rho_text +
                                " > 0; a fibre cell needs a unit fibre direction");

  const std::string short_ = variant("tangent_short", [&](openvdb::GridPtrVec& grids) {
    vec_grid(grids, "tangent").tree().setValue(c, openvdb::Vec3s(0.5f, 0, 0));
  });
  EXPECT_EQ(error_of(short_), short_ + ": tangent: " + where + " has length 0.5 where density is " +
                                  rho_text +
                                  " > 0; expected a unit vector (length within 0.01 of 1)");

  // Within the tolerance: normalised on reading.
  const std::string near = variant("tangent_near_unit", [&](openvdb::GridPtrVec& grids) {
    vec_grid(grids, "tangent").tree().setValue(c, openvdb::Vec3s(0, 1.005f, 0));
  });
  const VolumeTexture read = read_volume_vdb(near, k_budget);
  EXPECT_EQ(read.at(c.x(), c.y(), c.z()).tangent, Imath::V3f(0, 1, 0));
}

TEST_F(VdbReader, TooLargeForTheMemoryBudget) {
  ClothSpec spec;
  spec.resolution = {64, 64, 16, 1};
  const std::string path = (m_dir / "big.vdb").string();
  write_volume_vdb(path, generate_volume(spec, k_budget), "big");
  const uint64_t need = estimated_vdb_read_bytes(64 * 64 * 16);
  EXPECT_EQ(error_of(path, uint64_t(1) << 20), path + ": 64 x 64 x 16 voxels need an estimated " +
                                                   std::to_string(need / (1024 * 1024)) +
                                                   " MiB, over the memory budget of 1 MiB");
}

TEST_F(VdbReader, MemoryIsEstimatedBeforeAnyVoxelIsRead) {
  // The grids' metadata claim a huge box; the voxels are the small texture.
  // Refused by the estimate, so the claim was checked before the voxels.
  openvdb::io::File in(m_good);
  in.open();
  const openvdb::GridPtrVecPtr grids = in.getGrids();
  in.close();
  for (const auto& g : *grids) {
    g->insertMeta(openvdb::GridBase::META_FILE_BBOX_MIN, openvdb::Vec3IMetadata({0, 0, 0}));
    g->insertMeta(openvdb::GridBase::META_FILE_BBOX_MAX,
                  openvdb::Vec3IMetadata({99999, 99999, 999}));
  }
  const std::string path = (m_dir / "claims_huge.vdb").string();
  openvdb::io::File out(path);
  out.setGridStatsMetadataEnabled(false);  // keep the claim
  out.write(*grids);
  out.close();
  const uint64_t need = estimated_vdb_read_bytes(uint64_t(100000) * 100000 * 1000);
  EXPECT_EQ(error_of(path), path + ": 100000 x 100000 x 1000 voxels need an estimated " +
                                std::to_string(need / (1024 * 1024)) +
                                " MiB, over the memory budget of 1024 MiB");
}

TEST_F(VdbReader, OffsetGridStartsAtItsActiveBox) {
  // A texture edited elsewhere may sit anywhere in index space: its active
  // box's minimum becomes cell (0, 0, 0).
  const std::string path = variant("shifted", [](openvdb::GridPtrVec& grids) {
    for (auto& g : grids) {
      openvdb::GridBase::Ptr shifted = g->copyGridWithNewTree();
      openvdb::Coord offset(-8, 3, 100);
      if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g)) {
        auto out = openvdb::gridPtrCast<openvdb::FloatGrid>(shifted);
        for (auto it = f->cbeginValueOn(); it; ++it)
          out->tree().setValue(it.getCoord() + offset, *it);
      } else {
        auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g);
        auto out = openvdb::gridPtrCast<openvdb::Vec3SGrid>(shifted);
        for (auto it = v->cbeginValueOn(); it; ++it)
          out->tree().setValue(it.getCoord() + offset, *it);
      }
      g = shifted;
    }
  });
  const VolumeTexture read = read_volume_vdb(path, k_budget);
  ASSERT_EQ(read.cell_count(), m_volume.cell_count());
  for (size_t n = 0; n < read.cell_count(); ++n)
    ASSERT_EQ(read.cells()[n].density, m_volume.cells()[n].density) << n;
}

}  // namespace
}  // namespace clothbake::io
