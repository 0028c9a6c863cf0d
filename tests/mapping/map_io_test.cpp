// map.vdb round trip and its errors; the PLY files' headers and sizes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "core/error.h"
#include "core/file_bytes.h"
#include "mapping/map_io.h"

namespace pensight::mapping {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("pensight_map_io_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_bytes(const fs::path& file) {
  return read_file_bytes(file).value_or("");
}

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

size_t entries(const fs::path& dir) {
  return static_cast<size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

std::string error_of(const fs::path& file) {
  try {
    read_map_vdb(file);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// Occupied, free and weak voxels at random, and a saturated free tile.
OccupancyMap sample_map(const MapConfig& config) {
  OccupancyMap map(config);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coord(-40, 40);
  std::uniform_real_distribution<float> lo(-2.0f, 3.5f);
  for (int i = 0; i < 3000; ++i) {
    map.grid().tree().setValue(openvdb::Coord(coord(rng), coord(rng), coord(rng)), lo(rng));
  }
  map.grid().tree().addTile(1, openvdb::Coord(80, 0, 0), -2.0f, true);
  return map;
}

TEST(MapIoTest, VdbRoundTripKeepsVoxelsAndConfig) {
  MapConfig config;
  config.voxel_m = 0.03;
  config.hit_log_odds = 0.7;
  config.miss_log_odds = -0.3;
  config.min_log_odds = -1.5;
  config.max_log_odds = 3.0;
  config.occupied_log_odds = 0.25;
  config.min_range_m = 0.2;
  config.max_range_m = 4.0;
  config.free_margin_m = 0.01;
  config.threads = 2;
  const OccupancyMap map = sample_map(config);
  const fs::path dir = fresh_dir("round_trip");
  const fs::path file = dir / "map.vdb";
  write_map_vdb(map, file);
  EXPECT_EQ(entries(dir), 1u);  // no temporary left beside it
  const OccupancyMap back = read_map_vdb(file);
  MapConfig expected = config;
  expected.threads = 0;  // a property of the process, not of the map: not in the file
  EXPECT_TRUE(back.config() == expected);
  EXPECT_EQ(back.grid().activeVoxelCount(), map.grid().activeVoxelCount());
  EXPECT_EQ(back.grid().tree().activeTileCount(), map.grid().tree().activeTileCount());
  EXPECT_EQ(back.occupied_voxel_count(), map.occupied_voxel_count());
  auto same_values = [](const OccupancyMap& a, const OccupancyMap& b) {
    size_t n = 0;
    auto acc = b.grid().getConstAccessor();
    for (auto it = a.grid().cbeginValueOn(); it; ++it) {
      openvdb::CoordBBox box;
      it.getBoundingBox(box);
      for (const openvdb::Coord& p : box) {
        if (!acc.isValueOn(p) || acc.getValue(p) != *it) return false;
        ++n;
      }
    }
    return n == a.grid().activeVoxelCount();
  };
  EXPECT_TRUE(same_values(map, back));
  EXPECT_TRUE(same_values(back, map));
  fs::remove_all(dir);
}

TEST(MapIoTest, BadFilesNameTheFile) {
  const fs::path dir = fresh_dir("bad");
  const OccupancyMap map = sample_map(MapConfig{});
  write_map_vdb(map, dir / "map.vdb");
  const std::string good = read_bytes(dir / "map.vdb");
  ASSERT_GT(good.size(), 1000u);
  std::vector<fs::path> bad = {dir / "missing.vdb", dir / "text.vdb"};
  write_bytes(dir / "text.vdb", "voxel_m: 0.02\nthis is not an OpenVDB file\n");
  for (const size_t keep : {size_t{3}, size_t{40}, good.size() / 2, good.size() - 8}) {
    const fs::path cut = dir / ("truncated_" + std::to_string(keep) + ".vdb");
    write_bytes(cut, good.substr(0, keep));
    bad.push_back(cut);
  }
  {
    openvdb::FloatGrid::Ptr density = openvdb::FloatGrid::create(0.0f);
    density->setName("density");
    density->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    openvdb::io::File(dir.string() + "/density.vdb").write({density});
    bad.push_back(dir / "density.vdb");
  }
  for (const fs::path& file : bad) {
    const std::string message = error_of(file);
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  }
  EXPECT_NE(error_of(dir / "density.vdb").find("not written by pensight map"), std::string::npos);
  // One flipped byte inside the grid data is caught by the checksum before OpenVDB parses it.
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x10);
  write_bytes(dir / "flipped.vdb", flipped);
  EXPECT_NE(error_of(dir / "flipped.vdb").find("checksum mismatch"), std::string::npos);
  fs::remove_all(dir);
}

TEST(MapIoTest, FailedWriteNamesTheFileAndLeavesNoTemporary) {
  const fs::path dir = fresh_dir("failed_write");
  fs::create_directories(dir / "map.vdb" / "occupied");  // a non-empty folder where the file goes
  try {
    write_map_vdb(sample_map(MapConfig{}), dir / "map.vdb");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "map.vdb").string()), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(entries(dir), 1u);
  fs::remove_all(dir);
}

constexpr const char* kHeaderStart =
    "ply\nformat binary_little_endian 1.0\ncomment pensight map, frame P (pen), metres\n";
constexpr const char* kVertexProperties = "property float x\nproperty float y\nproperty float z\n";

TEST(MapIoTest, MeshPlyHeaderAndSize) {
  const fs::path dir = fresh_dir("mesh");
  SurfaceMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5f}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 4, 3}};
  mesh.quads = {{0, 1, 3, 2}};
  write_mesh_ply(mesh, dir / "map_mesh.ply");
  EXPECT_EQ(entries(dir), 1u);
  const std::string bytes = read_bytes(dir / "map_mesh.ply");
  const std::string header =
      std::string(kHeaderStart) + "element vertex 5\n" + kVertexProperties +
      "element face 3\nproperty list uchar uint vertex_indices\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  // 12 bytes per vertex; per face a count byte and 4 bytes per index.
  EXPECT_EQ(bytes.size(), header.size() + 5 * 12 + 2 * 13 + 17);
  float v3[3];
  std::memcpy(v3, bytes.data() + header.size() + 3 * 12, 12);
  EXPECT_EQ(v3[2], 0.5f);
  const char* faces = bytes.data() + header.size() + 5 * 12;
  uint32_t second[3];
  std::memcpy(second, faces + 14, 12);
  EXPECT_EQ(faces[13], 3);
  EXPECT_EQ(second[1], 4u);
  EXPECT_EQ(faces[26], 4);

  // The mesh of a real map: the counts in the header are the mesh's.
  OccupancyMap map{MapConfig{}};
  for (int x = 0; x < 6; ++x) {
    for (int y = 0; y < 6; ++y) map.grid().tree().setValue(openvdb::Coord(x, y, 0), 3.5f);
  }
  const SurfaceMesh surface = extract_surface(map);
  ASSERT_GT(surface.vertices.size(), 0u);
  write_mesh_ply(surface, dir / "surface.ply");
  const std::string s = read_bytes(dir / "surface.ply");
  const std::string h = std::string(kHeaderStart) + "element vertex " +
                        std::to_string(surface.vertices.size()) + "\n" + kVertexProperties +
                        "element face " +
                        std::to_string(surface.triangles.size() + surface.quads.size()) +
                        "\nproperty list uchar uint vertex_indices\nend_header\n";
  ASSERT_EQ(s.substr(0, h.size()), h);
  EXPECT_EQ(s.size(), h.size() + surface.vertices.size() * 12 + surface.triangles.size() * 13 +
                          surface.quads.size() * 17);
  fs::remove_all(dir);
}

TEST(MapIoTest, PointsPlyHoldsEveryOccupiedVoxelCentre) {
  const fs::path dir = fresh_dir("points");
  OccupancyMap map = sample_map(MapConfig{});
  map.grid().tree().addTile(1, openvdb::Coord(-80, 0, 0), 2.0f, true);  // 512 occupied voxels
  write_points_ply(map, dir / "map_points.ply");
  EXPECT_EQ(entries(dir), 1u);
  const size_t n = map.occupied_voxel_count();
  ASSERT_GT(n, 512u);
  const std::string bytes = read_bytes(dir / "map_points.ply");
  const std::string header = std::string(kHeaderStart) + "element vertex " + std::to_string(n) +
                             "\n" + kVertexProperties + "end_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  ASSERT_EQ(bytes.size(), header.size() + n * 12);
  const double v = map.config().voxel_m;
  for (size_t i = 0; i < n; ++i) {
    float p[3];
    std::memcpy(p, bytes.data() + header.size() + 12 * i, 12);
    const Eigen::Vector3d point(p[0], p[1], p[2]);
    ASSERT_EQ(map.occupancy_at(point), Occupancy::kOccupied) << "point " << i;
    // A voxel centre, to float precision.
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(point[a] / v, std::round(point[a] / v), 1e-4);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pensight::mapping
