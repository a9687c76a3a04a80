#include "io/vdb_writer.h"

#include <sstream>

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include "core/util/error.h"
#include "io/atomic_file.h"

namespace clothbake::io {

namespace {

template <typename GridT, typename Get>
typename GridT::Ptr make_grid(const VolumeTexture& volume, const char* name,
                              const openvdb::math::Transform::Ptr& xform, Get get) {
  auto grid = GridT::create(typename GridT::ValueType(0));
  grid->setName(name);
  grid->setTransform(xform);
  auto acc = grid->getAccessor();
  // setValue on every cell activates each voxel individually; nothing is
  // pruned afterwards, so no region becomes a constant tile.
  for (int k = 0; k < volume.nz(); ++k)
    for (int j = 0; j < volume.ny(); ++j)
      for (int i = 0; i < volume.nx(); ++i)
        acc.setValue(openvdb::Coord(i, j, k), get(volume.at(i, j, k)));
  return grid;
}

}  // namespace

void write_volume_vdb_to(const std::string& temp, const std::string& path,
                         const VolumeTexture& volume, const std::string& description) {
  openvdb::initialize();
  const Imath::V3f cell = volume.cell_size_mm();
  openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
  m.setToScale(openvdb::Vec3d(cell.x, cell.y, cell.z));
  m.setTranslation(openvdb::Vec3d(0.5 * cell.x, 0.5 * cell.y, 0.5 * cell.z));
  auto xform = openvdb::math::Transform::createLinearTransform(m);

  auto to_vec = [](const Imath::V3f& v) { return openvdb::Vec3s(v.x, v.y, v.z); };
  openvdb::GridPtrVec grids;
  grids.push_back(make_grid<openvdb::FloatGrid>(volume, "density", xform,
                                                [](const Cell& c) { return c.density; }));
  auto tangent = make_grid<openvdb::Vec3SGrid>(volume, "tangent", xform,
                                               [&](const Cell& c) { return to_vec(c.tangent); });
  tangent->setVectorType(openvdb::VEC_INVARIANT);
  grids.push_back(tangent);
  grids.push_back(make_grid<openvdb::Vec3SGrid>(volume, "diffuse", xform,
                                                [&](const Cell& c) { return to_vec(c.diffuse); }));
  grids.push_back(make_grid<openvdb::FloatGrid>(volume, "specular", xform,
                                                [](const Cell& c) { return c.specular; }));
  grids.push_back(make_grid<openvdb::FloatGrid>(volume, "exponent", xform,
                                                [](const Cell& c) { return c.exponent; }));

  openvdb::MetaMap meta;
  meta.insertMeta("creator", openvdb::StringMetadata("clothbake"));
  meta.insertMeta("clothbake_description", openvdb::StringMetadata(description));
  meta.insertMeta("clothbake_units", openvdb::StringMetadata("mm"));
  meta.insertMeta("clothbake_size_mm",
                  openvdb::Vec3DMetadata(
                      openvdb::Vec3d(volume.size_mm().x, volume.size_mm().y, volume.size_mm().z)));
  // OpenVDB's file writer does not report a failed write (a full disk or a
  // file size limit left an 8 KiB file and exit status 0): the grids are
  // serialised in memory and written by write_bytes_checked.
  std::ostringstream bytes(std::ios_base::out | std::ios_base::binary);
  try {
    openvdb::io::Stream(bytes).write(grids, meta);
  } catch (const openvdb::Exception& e) {
    throw InputError("", std::string("cannot write VDB: ") + e.what(), path);
  }
  const std::string data = std::move(bytes).str();
  write_bytes_checked(temp, path, data.data(), data.size());
}

void write_volume_vdb(const std::string& path, const VolumeTexture& volume,
                      const std::string& description) {
  write_atomically(
      path, [&](const std::string& temp) { write_volume_vdb_to(temp, path, volume, description); });
}

}  // namespace clothbake::io
