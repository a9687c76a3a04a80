#include "io/vdb_writer.h"

#include <filesystem>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include "core/texture/volume_generator.h"

namespace clothbake::io {
namespace {

TEST(VdbWriter, EveryCellIsAnActiveVoxelAtItsCellCentre) {
  ClothSpec spec;
  spec.resolution = {16, 16, 6, 1};
  const VolumeTexture volume = generate_volume(spec, uint64_t(1) << 30);
  const auto path = std::filesystem::temp_directory_path() / "clothbake_vdb_writer_test.vdb";
  write_volume_vdb(path.string(), volume, "test");

  openvdb::initialize();
  openvdb::io::File file(path.string());
  file.open();
  const auto grids = file.getGrids();
  file.close();
  std::filesystem::remove(path);
  ASSERT_EQ(grids->size(), std::size(k_vdb_grid_names));
  auto find = [&](const char* name) {
    for (const auto& g : *grids)
      if (g->getName() == name) return g;
    return openvdb::GridBase::Ptr();
  };
  for (const char* name : k_vdb_grid_names) {
    const auto grid = find(name);
    ASSERT_TRUE(grid) << "no grid named " << name;
    EXPECT_EQ(grid->activeVoxelCount(), volume.cell_count()) << grid->getName();
    // No constant tiles: every active value sits in a leaf voxel.
    EXPECT_EQ(grid->baseTree().activeLeafVoxelCount(), volume.cell_count()) << grid->getName();
  }
  auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(find("density"));
  auto tangent = openvdb::gridPtrCast<openvdb::Vec3SGrid>(find("tangent"));
  ASSERT_TRUE(density && tangent);
  const Imath::V3f cell = volume.cell_size_mm();
  for (auto [i, j, k] : {std::tuple{0, 0, 0}, std::tuple{5, 9, 3}, std::tuple{15, 15, 5}}) {
    const openvdb::Coord c(i, j, k);
    EXPECT_EQ(density->tree().getValue(c), volume.at(i, j, k).density);
    EXPECT_EQ(tangent->tree().getValue(c).x(), volume.at(i, j, k).tangent.x);
    const openvdb::Vec3d world = density->indexToWorld(c);
    EXPECT_NEAR(world.x(), (i + 0.5) * cell.x, 1e-6);
    EXPECT_NEAR(world.y(), (j + 0.5) * cell.y, 1e-6);
    EXPECT_NEAR(world.z(), (k + 0.5) * cell.z, 1e-6);
  }
}

}  // namespace
}  // namespace clothbake::io
