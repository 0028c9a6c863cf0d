// `pensight map-query MAP.vdb [--at X Y Z] [--ray OX OY OZ DX DY DZ] [--nearest X Y Z]`: what a
// map written by `pensight map` or `pensight run --map` holds, and its queries, in P (metres).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "apps/command.h"
#include "mapping/map_io.h"

namespace pensight::app {
namespace {

const char* name(mapping::Occupancy o) {
  switch (o) {
    case mapping::Occupancy::kOccupied:
      return "occupied";
    case mapping::Occupancy::kFree:
      return "free";
    case mapping::Occupancy::kUnknown:
      break;
  }
  return "unknown";
}

}  // namespace

int cmd_map_query(const Args& args) {
  CLI::App cli("Describe an occupancy map (map.vdb) and answer point, ray and distance queries",
               "pensight map-query");
  std::string file;
  std::vector<double> at, ray, nearest;
  double max_distance_m = 5.0;
  cli.add_option("MAP", file, "map.vdb written by pensight map or pensight run --map")->required();
  cli.add_option("--at", at, "X Y Z: occupancy of the voxel holding this point")->expected(3);
  cli.add_option("--ray", ray, "OX OY OZ DX DY DZ: first occupied voxel along the ray")
      ->expected(6);
  cli.add_option("--nearest", nearest, "X Y Z: distance to the nearest occupied voxel")
      ->expected(3);
  cli.add_option("--max-distance", max_distance_m, "search limit of --ray and --nearest [m]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  const mapping::OccupancyMap map = mapping::read_map_vdb(file);
  const openvdb::CoordBBox box = map.grid().evalActiveVoxelBoundingBox();
  const double v = map.config().voxel_m;
  std::printf(
      "%s: voxel %.0f mm, %llu observed voxels, %zu occupied, %.1f MB in memory; observed box "
      "[%.2f %.2f %.2f] - [%.2f %.2f %.2f] m (P)\n",
      file.c_str(), v * 1e3, static_cast<unsigned long long>(map.grid().activeVoxelCount()),
      map.occupied_voxel_count(), static_cast<double>(map.memory_bytes()) / 1e6, box.min().x() * v,
      box.min().y() * v, box.min().z() * v, box.max().x() * v, box.max().y() * v,
      box.max().z() * v);
  if (!at.empty()) {
    const Eigen::Vector3d p(at[0], at[1], at[2]);
    std::printf("at [%g %g %g]: %s (log-odds %.2f)\n", p.x(), p.y(), p.z(),
                name(map.occupancy_at(p)), map.log_odds_at(p));
  }
  if (!ray.empty()) {
    const Eigen::Vector3d o(ray[0], ray[1], ray[2]), d(ray[3], ray[4], ray[5]);
    if (const auto hit = map.first_occupied_along_ray(o, d, max_distance_m)) {
      std::printf("ray: first occupied voxel at [%.3f %.3f %.3f], %.3f m from the origin\n",
                  hit->x(), hit->y(), hit->z(), (*hit - o).norm());
    } else {
      std::printf("ray: no occupied voxel within %g m\n", max_distance_m);
    }
  }
  if (!nearest.empty()) {
    const double d = map.distance_to_occupied({nearest[0], nearest[1], nearest[2]}, max_distance_m);
    if (std::isinf(d)) {
      std::printf("nearest: no occupied voxel within %g m\n", max_distance_m);
    } else {
      std::printf("nearest occupied voxel: %.3f m\n", d);
    }
  }
  return 0;
}

PENSIGHT_COMMAND("map-query", "describe a map.vdb and answer point, ray and distance queries",
                 cmd_map_query);

}  // namespace pensight::app
