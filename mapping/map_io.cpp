#include "mapping/map_io.h"

#include <openvdb/io/Stream.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "pipeline/dataset/atomic_file.h"
#include "runtime/error.h"

namespace pensight::mapping {
namespace {

// Metadata keys of map.vdb: MapConfig's members, prefixed.
struct MetaKey {
  const char* name;
  double MapConfig::*member;
};
constexpr MetaKey kMetaKeys[] = {
    {"pensight_hit_log_odds", &MapConfig::hit_log_odds},
    {"pensight_miss_log_odds", &MapConfig::miss_log_odds},
    {"pensight_min_log_odds", &MapConfig::min_log_odds},
    {"pensight_max_log_odds", &MapConfig::max_log_odds},
    {"pensight_occupied_log_odds", &MapConfig::occupied_log_odds},
    {"pensight_min_range_m", &MapConfig::min_range_m},
    {"pensight_max_range_m", &MapConfig::max_range_m},
    {"pensight_free_margin_m", &MapConfig::free_margin_m},
};

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void write_ply(const std::filesystem::path& file, const std::vector<Eigen::Vector3f>& vertices,
               const SurfaceMesh* faces) {
  const size_t n_faces = faces ? faces->triangles.size() + faces->quads.size() : 0;
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment pensight map, frame P (pen), metres\n"
      "element vertex " +
      std::to_string(vertices.size()) + "\nproperty float x\nproperty float y\nproperty float z\n";
  if (faces) {
    out +=
        "element face " + std::to_string(n_faces) + "\nproperty list uchar uint vertex_indices\n";
  }
  out += "end_header\n";
  out.reserve(out.size() + vertices.size() * 12 + n_faces * 17);
  for (const Eigen::Vector3f& p : vertices) {
    put(out, p.x());
    put(out, p.y());
    put(out, p.z());
  }
  if (faces) {
    for (const auto& t : faces->triangles) {
      put(out, static_cast<uint8_t>(3));
      for (uint32_t i : t) put(out, i);
    }
    for (const auto& q : faces->quads) {
      put(out, static_cast<uint8_t>(4));
      for (uint32_t i : q) put(out, i);
    }
  }
  write_file_atomically(file, out);
}

}  // namespace

SurfaceMesh extract_surface(const OccupancyMap& map) {
  // volumeToMesh meshes where its input crosses the isovalue and takes values below it as inside.
  // Its input: occupied voxels at minus their log-odds (inside), every other voxel, unknown ones
  // included, at kOutside. Unknown voxels sit at log-odds 0 themselves, which would put the
  // surface on every unknown voxel centre next to an occupied one, a voxel off a net seen from one
  // side. With kOutside = 3 x max_log_odds the crossing lies a quarter voxel from a saturated
  // occupied voxel's centre (3.5 / (3.5 + 10.5)), so the shell around a one-voxel sheet of twine
  // is half a voxel thick and centred on it.
  const auto occupied = static_cast<float>(map.config().occupied_log_odds);  // as the queries
  const auto outside = static_cast<float>(3 * map.config().max_log_odds);
  openvdb::FloatGrid::Ptr field = openvdb::FloatGrid::create(outside);
  field->setTransform(map.grid().transform().copy());
  field->tree().topologyUnion(map.grid().tree());
  auto src = map.grid().getConstAccessor();
  for (auto it = field->tree().beginLeaf(); it; ++it) {
    for (auto v = it->beginValueAll(); v; ++v) {
      const float l = src.getValue(v.getCoord());
      v.setValue(l > occupied ? -l : outside);
    }
  }
  field->tree().voxelizeActiveTiles();
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*field, points, triangles, quads, 0.0);
  SurfaceMesh mesh;
  mesh.vertices.reserve(points.size());
  for (const auto& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  for (const auto& t : triangles) mesh.triangles.push_back({t.x(), t.y(), t.z()});
  for (const auto& q : quads) mesh.quads.push_back({q[0], q[1], q[2], q[3]});
  return mesh;
}

void write_map_vdb(const OccupancyMap& map, const std::filesystem::path& file) {
  openvdb::FloatGrid::ConstPtr shared = map.grid().copy();  // shares the tree; own metadata
  openvdb::FloatGrid::Ptr grid = openvdb::ConstPtrCast<openvdb::FloatGrid>(shared);
  grid->setName("occupancy");
  grid->setGridClass(openvdb::GRID_UNKNOWN);
  grid->insertMeta("pensight_frame", openvdb::StringMetadata("P (pen), metres"));
  grid->insertMeta("pensight_values", openvdb::StringMetadata("log-odds occupancy"));
  for (const MetaKey& k : kMetaKeys) {
    grid->insertMeta(k.name, openvdb::DoubleMetadata(map.config().*k.member));
  }
  const std::filesystem::path temp = temporary_sibling(file);
  try {
    openvdb::io::File out(temp.string());
    out.write({grid});
    out.close();
  } catch (const openvdb::Exception& e) {
    std::filesystem::remove(temp);
    throw Error("cannot write map '" + file.string() + "': " + e.what());
  }
  std::error_code ec;
  std::filesystem::rename(temp, file, ec);
  if (ec) {
    std::filesystem::remove(temp);
    throw Error("cannot write map '" + file.string() + "': " + ec.message());
  }
}

OccupancyMap read_map_vdb(const std::filesystem::path& file) {
  openvdb::initialize();
  if (!std::filesystem::is_regular_file(file)) {
    throw Error("map '" + file.string() +
                "': no such file (give the map.vdb that pensight map wrote)");
  }
  // Read through a stream that throws on a short read: OpenVDB's own file reader takes the size
  // of a compressed block from the bytes where a truncated file ends and allocates that much.
  openvdb::GridBase::Ptr base;
  try {
    std::ifstream in(file, std::ios::binary);
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::io::Stream stream(in, false);
    for (const openvdb::GridBase::Ptr& g : *stream.getGrids()) {
      if (g->getName() == "occupancy") base = g;
    }
  } catch (const std::ios_base::failure&) {
    throw Error("map '" + file.string() + "': truncated (the file ends inside its grid data)");
  } catch (const std::exception& e) {  // openvdb::Exception, std::bad_alloc from corrupt sizes
    throw Error("map '" + file.string() + "': not a readable OpenVDB file (" + e.what() + ")");
  }
  if (!base) {
    throw Error("map '" + file.string() +
                "': no grid named 'occupancy' (not a pensight map; pensight map writes one)");
  }
  openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  if (!grid) {
    throw Error("map '" + file.string() + "': grid 'occupancy' is of type " + base->valueType() +
                ", not float log-odds");
  }
  const openvdb::math::Transform& tf = grid->transform();
  const openvdb::Vec3d voxel = tf.voxelSize();
  if (!tf.isLinear() || !(voxel.x() == voxel.y() && voxel.y() == voxel.z())) {
    throw Error("map '" + file.string() + "': grid 'occupancy' has no uniform linear voxel size");
  }
  MapConfig config;
  config.voxel_m = voxel.x();
  for (const MetaKey& k : kMetaKeys) {
    if (auto m = grid->getMetadata<openvdb::DoubleMetadata>(k.name)) config.*k.member = m->value();
  }
  try {
    return OccupancyMap(config, grid);
  } catch (const Error& e) {
    throw Error("map '" + file.string() + "': " + e.what());
  }
}

SurfaceMesh write_map_outputs(const OccupancyMap& map, const std::filesystem::path& dir) {
  write_map_vdb(map, dir / "map.vdb");
  SurfaceMesh mesh = extract_surface(map);
  write_mesh_ply(mesh, dir / "map_mesh.ply");
  write_points_ply(map, dir / "map_points.ply");
  return mesh;
}

void write_mesh_ply(const SurfaceMesh& mesh, const std::filesystem::path& file) {
  write_ply(file, mesh.vertices, &mesh);
}

void write_points_ply(const OccupancyMap& map, const std::filesystem::path& file) {
  const auto threshold = static_cast<float>(map.config().occupied_log_odds);
  const double v = map.config().voxel_m;
  std::vector<Eigen::Vector3f> points;
  for (auto it = map.grid().cbeginValueOn(); it; ++it) {
    if (*it <= threshold) continue;
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (const openvdb::Coord& c : box) {
      points.emplace_back(static_cast<float>(c.x() * v), static_cast<float>(c.y() * v),
                          static_cast<float>(c.z() * v));
    }
  }
  write_ply(file, points, nullptr);
}

}  // namespace pensight::mapping
