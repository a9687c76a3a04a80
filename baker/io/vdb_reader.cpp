#include "io/vdb_reader.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include <openvdb/openvdb.h>

#include "core/util/error.h"
#include "io/vdb_writer.h"

namespace clothbake::io {

namespace {

namespace fs = std::filesystem;

constexpr int k_grid_count = 5;
// The value type each grid of k_vdb_grid_names must have (GridBase::valueType()).
constexpr const char* k_value_types[k_grid_count] = {"float", "vec3s", "vec3s", "float", "float"};

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string fmt(const openvdb::Vec3d& v) {
  return "[" + fmt(v.x()) + ", " + fmt(v.y()) + ", " + fmt(v.z()) + "]";
}

std::string fmt(const openvdb::Coord& c) {
  return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) +
         ")";
}

std::string fmt(const openvdb::Vec3s& v) {
  return "[" + fmt(v.x()) + ", " + fmt(v.y()) + ", " + fmt(v.z()) + "]";
}

std::string bbox_text(const openvdb::CoordBBox& box) {
  return fmt(box.min()) + " to " + fmt(box.max());
}

/// The grid's affine index-to-world matrix, or a refusal naming the grid:
/// only linear, axis-aligned maps with a positive scale give clothbake cells.
openvdb::Vec3d voxel_size_of(const openvdb::GridBase& grid, const std::string& path) {
  const std::string name = grid.getName();
  const openvdb::math::Transform& xform = grid.transform();
  if (!xform.isLinear())
    throw InputError(name,
                     "transform is not linear (" + xform.mapType() +
                         "): the voxel size varies across the grid; clothbake needs one voxel "
                         "size for the whole grid",
                     path);
  const openvdb::Mat4d m = xform.baseMap()->getAffineMap()->getMat4();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c && m(r, c) != 0.0)
        throw InputError(name,
                         "transform rotates or shears the grid; clothbake needs an axis-aligned "
                         "grid (a scale and an offset)",
                         path);
  const openvdb::Vec3d size(m(0, 0), m(1, 1), m(2, 2));
  if (!(size.x() > 0.0 && size.y() > 0.0 && size.z() > 0.0) || !std::isfinite(size.x()) ||
      !std::isfinite(size.y()) || !std::isfinite(size.z()))
    throw InputError(
        name, "voxel size " + fmt(size) + " mm is not positive and finite on every axis", path);
  return size;
}

/// The active bounding box recorded in the grid's metadata by the writer of
/// the file (OpenVDB adds it by default), if present.
std::optional<openvdb::CoordBBox> metadata_bbox(const openvdb::GridBase& grid) {
  const auto lo = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MIN);
  const auto hi = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MAX);
  if (!lo || !hi) return std::nullopt;
  const openvdb::Vec3i a = lo->value(), b = hi->value();
  return openvdb::CoordBBox(openvdb::Coord(a.x(), a.y(), a.z()),
                            openvdb::Coord(b.x(), b.y(), b.z()));
}

bool finite(float x) { return std::isfinite(x); }
bool finite(const openvdb::Vec3s& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

/// Copies one grid's values over `box` into the cells, refusing non-finite
/// values (naming the voxel in index space) and whatever `check` refuses.
template <class GridT, class Store>
void copy_grid(const GridT& grid, const openvdb::CoordBBox& box, VolumeTexture& volume,
               const std::string& path, Store store) {
  auto acc = grid.getConstAccessor();
  const openvdb::Coord lo = box.min();
  for (int k = 0; k < volume.nz(); ++k)
    for (int j = 0; j < volume.ny(); ++j)
      for (int i = 0; i < volume.nx(); ++i) {
        const openvdb::Coord ijk = lo.offsetBy(i, j, k);
        const auto value = acc.getValue(ijk);
        if (!finite(value))
          throw InputError(grid.getName(),
                           "voxel " + fmt(ijk) + " is not a finite number; values must be finite",
                           path);
        const std::string problem = store(volume.at(i, j, k), value);
        if (!problem.empty())
          throw InputError(grid.getName(), "voxel " + fmt(ijk) + " " + problem, path);
      }
}

}  // namespace

uint64_t estimated_vdb_read_bytes(uint64_t cell_count) {
  // The dense cells, plus the five grids' leaf values (4 + 12 + 12 + 4 + 4
  // bytes a voxel) and their leaf masks, about an eighth more.
  const uint64_t grid_bytes = 36 + 36 / 8;
  return cell_count * (sizeof(Cell) + grid_bytes);
}

// About 155 lines, kept whole: opens the file and reads and checks its
// grids in order (metadata, density, tangent, shading), each error naming
// the file and the grid.
VolumeTexture read_volume_vdb(const std::string& path, uint64_t memory_budget_bytes) {
  // Step 1: the file.
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError("", "cannot open file (missing or unreadable)", path);
  if (fs::is_directory(path, ec)) throw InputError("", "is a directory, expected a VDB file", path);
  openvdb::initialize();
  openvdb::io::File file(path);
  try {
    file.open(/*delayLoad=*/false);
  } catch (const openvdb::Exception& e) {
    throw InputError("", std::string("not a readable OpenVDB file (") + e.what() + ")", path);
  }

  // Step 2: the five grids' metadata and transforms, before any voxel.
  openvdb::GridBase::Ptr meta[k_grid_count];
  openvdb::Vec3d voxel_mm[k_grid_count];
  for (int g = 0; g < k_grid_count; ++g) {
    const std::string name = k_vdb_grid_names[g];
    if (!file.hasGrid(name))
      throw InputError(name,
                       "grid missing; a clothbake volume needs the grids density (float), "
                       "tangent (vec3s), diffuse (vec3s), specular (float) and exponent (float)",
                       path);
    try {
      meta[g] = file.readGridMetadata(name);
    } catch (const openvdb::Exception& e) {
      throw InputError(name, std::string("cannot read the grid (") + e.what() + ")", path);
    }
    if (meta[g]->valueType() != k_value_types[g])
      throw InputError(
          name,
          "grid has values of type " + meta[g]->valueType() + "; expected " + k_value_types[g],
          path);
    voxel_mm[g] = voxel_size_of(*meta[g], path);
    if (g > 0 && !(meta[g]->transform() == meta[0]->transform()))
      throw InputError(name,
                       "transform (voxel size " + fmt(voxel_mm[g]) +
                           " mm) differs from the density grid's (voxel size " + fmt(voxel_mm[0]) +
                           " mm); all five grids must share one transform",
                       path);
  }

  // Step 3: the active bounding boxes from the metadata, and the memory estimate.
  std::optional<openvdb::CoordBBox> boxes[k_grid_count];
  for (int g = 0; g < k_grid_count; ++g) {
    boxes[g] = metadata_bbox(*meta[g]);
    const auto count =
        meta[g]->getMetadata<openvdb::Int64Metadata>(openvdb::GridBase::META_FILE_VOXEL_COUNT);
    if ((count && count->value() == 0) || (boxes[g] && boxes[g]->empty()))
      throw InputError(k_vdb_grid_names[g], "grid is empty (no active voxels)", path);
  }
  auto check_budget = [&](const openvdb::CoordBBox& box) {
    const openvdb::Coord d = box.dim();
    const uint64_t cells = uint64_t(d.x()) * uint64_t(d.y()) * uint64_t(d.z());
    const uint64_t need = estimated_vdb_read_bytes(cells);
    if (need > memory_budget_bytes)
      throw InputError("",
                       std::to_string(d.x()) + " x " + std::to_string(d.y()) + " x " +
                           std::to_string(d.z()) + " voxels need an estimated " +
                           std::to_string(need / (1024 * 1024)) +
                           " MiB, over the memory budget of " +
                           std::to_string(memory_budget_bytes / (1024 * 1024)) + " MiB",
                       path);
  };
  for (int g = 0; g < k_grid_count; ++g)
    if (boxes[g]) check_budget(*boxes[g]);

  // Step 4: the voxels; the boxes again from the trees (the metadata is optional).
  openvdb::GridBase::Ptr grids[k_grid_count];
  for (int g = 0; g < k_grid_count; ++g) {
    try {
      grids[g] = file.readGrid(k_vdb_grid_names[g]);
    } catch (const openvdb::Exception& e) {
      throw InputError(k_vdb_grid_names[g], std::string("cannot read the grid (") + e.what() + ")",
                       path);
    }
    if (grids[g]->activeVoxelCount() == 0)
      throw InputError(k_vdb_grid_names[g], "grid is empty (no active voxels)", path);
    boxes[g] = grids[g]->evalActiveVoxelBoundingBox();
  }
  file.close();
  const openvdb::CoordBBox box = *boxes[0];
  for (int g = 1; g < k_grid_count; ++g)
    if (*boxes[g] != box)
      throw InputError(k_vdb_grid_names[g],
                       "active voxels span " + bbox_text(*boxes[g]) +
                           " (index space), the density grid's span " + bbox_text(box) +
                           "; all five grids must cover the same voxels",
                       path);
  check_budget(box);

  // Step 5: the texture's size, exactly as written by clothbake when it says so.
  const openvdb::Coord dim = box.dim();
  const openvdb::Vec3d& vs = voxel_mm[0];
  openvdb::Vec3d size_mm(dim.x() * vs.x(), dim.y() * vs.y(), dim.z() * vs.z());
  if (const auto written = grids[0]->getMetadata<openvdb::Vec3DMetadata>("clothbake_size_mm")) {
    const openvdb::Vec3d w = written->value();
    bool agrees = true;
    for (int a = 0; a < 3; ++a) agrees = agrees && std::abs(w[a] - size_mm[a]) <= 1e-5 * size_mm[a];
    if (agrees) size_mm = w;
  }
  VolumeTexture volume(dim.x(), dim.y(), dim.z(),
                       Imath::V3f(float(size_mm.x()), float(size_mm.y()), float(size_mm.z())));

  // Step 6: the cells, grid by grid, each value checked.
  using openvdb::FloatGrid;
  using openvdb::Vec3s;
  using openvdb::Vec3SGrid;
  auto as_float = [](const openvdb::GridBase::Ptr& g) -> const FloatGrid& {
    return *openvdb::gridConstPtrCast<FloatGrid>(g);
  };
  auto as_vec = [](const openvdb::GridBase::Ptr& g) -> const Vec3SGrid& {
    return *openvdb::gridConstPtrCast<Vec3SGrid>(g);
  };
  copy_grid(as_float(grids[0]), box, volume, path, [](Cell& c, float rho) -> std::string {
    if (!(rho >= 0.0f && rho <= 1.0f)) return "is " + fmt(rho) + "; density must be in [0, 1]";
    c.density = rho;
    return {};
  });
  copy_grid(as_vec(grids[1]), box, volume, path, [](Cell& c, const Vec3s& v) -> std::string {
    if (c.density > 0.0f) {
      const double length =
          std::sqrt(double(v.x()) * v.x() + double(v.y()) * v.y() + double(v.z()) * v.z());
      if (length == 0.0)
        return "is zero where density is " + fmt(c.density) +
               " > 0; a fibre cell needs a unit fibre direction";
      if (std::abs(length - 1.0) > k_vdb_tangent_tolerance)
        return "has length " + fmt(length) + " where density is " + fmt(c.density) +
               " > 0; expected a unit vector (length within " + fmt(k_vdb_tangent_tolerance) +
               " of 1)";
      // Unit to float precision: kept bit for bit; otherwise normalised.
      const Imath::V3f t(v.x(), v.y(), v.z());
      c.tangent = std::abs(length - 1.0) <= 1e-6 ? t : t / float(length);
    } else {
      c.tangent = Imath::V3f(v.x(), v.y(), v.z());
    }
    return {};
  });
  copy_grid(as_vec(grids[2]), box, volume, path, [](Cell& c, const Vec3s& v) -> std::string {
    if (v.x() < 0.0f || v.y() < 0.0f || v.z() < 0.0f)
      return "is " + fmt(v) + "; diffuse colours must be >= 0";
    c.diffuse = Imath::V3f(v.x(), v.y(), v.z());
    return {};
  });
  copy_grid(as_float(grids[3]), box, volume, path, [](Cell& c, float s) -> std::string {
    if (s < 0.0f) return "is " + fmt(s) + "; specular strength must be >= 0";
    c.specular = s;
    return {};
  });
  copy_grid(as_float(grids[4]), box, volume, path, [](Cell& c, float e) -> std::string {
    if (e < 0.0f) return "is " + fmt(e) + "; the Phong exponent must be >= 0";
    c.exponent = e;
    return {};
  });
  return volume;
}

}  // namespace clothbake::io
