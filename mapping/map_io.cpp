#include "mapping/map_io.h"

#include <openvdb/io/Stream.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_bytes.h"
#include "mapping/vdb_layout.h"

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

// map.vdb ends with a trailer after the OpenVDB data: kTrailerTag, the CRC-32 of every byte
// before the trailer (little-endian), kTrailerVersion. OpenVDB readers stop at the end of the
// grids, so the file stays a plain .vdb for other tools. The CRC is checked before OpenVDB parses
// anything: its decoder (10.0) trusts the block sizes inside the file and writes past its buffers
// on a damaged one (docs/reliability.md); a crafted one with a correct CRC is refused by its
// layout (vdb_layout.h).
constexpr char kTrailerTag[8] = {'p', 'e', 'n', 's', 'i', 'g', 'h', 't'};
constexpr char kTrailerVersion[4] = {'m', 'a', 'p', '1'};
constexpr size_t kTrailerSize = sizeof kTrailerTag + 4 + sizeof kTrailerVersion;

uint32_t crc32_of(std::string_view bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  for (size_t at = 0; at < bytes.size();) {
    const auto n = static_cast<uInt>(std::min<size_t>(bytes.size() - at, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + at), n);
    at += n;
  }
  return static_cast<uint32_t>(crc);
}

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
  const auto fail = [&](const char* why) {
    return Error("cannot write map '" + file.string() + "': " + why);
  };
  try {
    AtomicFile out(file);
    openvdb::io::File vdb(out.temp_path().string());
    vdb.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK);  // no zip or blosc: vdb_layout.h
    vdb.write({grid});
    vdb.close();
    const std::optional<std::string> bytes = read_file_bytes(out.temp_path());
    if (!bytes) throw openvdb::IoError("reading back the written grids failed");
    std::string trailer(kTrailerTag, sizeof kTrailerTag);
    put(trailer, crc32_of(*bytes));
    trailer.append(kTrailerVersion, sizeof kTrailerVersion);
    out.stream().seekp(0, std::ios::end);
    out.stream().write(trailer.data(), static_cast<std::streamsize>(trailer.size()));
    out.commit();
  } catch (const openvdb::Exception& e) {
    throw fail(e.what());
  } catch (const Error& e) {
    throw fail(e.what());
  }
}

OccupancyMap read_map_vdb(const std::filesystem::path& file) {
  openvdb::initialize();
  if (!std::filesystem::is_regular_file(file)) {
    throw Error("map '" + file.string() +
                "': no such file (give the map.vdb that pensight map wrote)");
  }
  std::string bytes = read_file_bytes(file).value_or("");
  const std::string_view data(bytes.data(),
                              bytes.size() < kTrailerSize ? 0 : bytes.size() - kTrailerSize);
  const std::string_view trailer = std::string_view(bytes).substr(data.size());
  if (trailer.size() != kTrailerSize ||
      trailer.substr(0, sizeof kTrailerTag) != std::string_view(kTrailerTag, sizeof kTrailerTag) ||
      trailer.substr(12) != std::string_view(kTrailerVersion, sizeof kTrailerVersion)) {
    throw Error("map '" + file.string() +
                "': no pensight checksum trailer (a truncated file, or not written by pensight "
                "map; re-run pensight map to write it)");
  }
  uint32_t stored = 0;
  std::memcpy(&stored, trailer.data() + sizeof kTrailerTag, 4);
  if (stored != crc32_of(data)) {
    throw Error("map '" + file.string() +
                "': checksum mismatch (the file is damaged; re-run pensight map to write it)");
  }
  try {
    check_vdb_layout(data);
  } catch (const Error& e) {
    throw Error("map '" + file.string() + "': " + e.what());
  }
  // Parse through a stream that throws on a short read: OpenVDB's own file reader takes the size
  // of a compressed block from the bytes where a file ends and allocates that much.
  openvdb::GridBase::Ptr base;
  try {
    bytes.resize(data.size());  // the grids without the trailer, moved into the stream
    std::istringstream in(std::move(bytes), std::ios::binary);
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

std::vector<Eigen::Vector3f> occupied_voxel_centres(const OccupancyMap& map) {
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
  return points;
}

void write_points_ply(const OccupancyMap& map, const std::filesystem::path& file) {
  write_ply(file, occupied_voxel_centres(map), nullptr);
}

}  // namespace pensight::mapping
