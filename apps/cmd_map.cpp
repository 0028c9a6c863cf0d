// `pensight map DATASET --out OUT [--from-truth]`: integrates a dataset's depth images and poses
// into the OpenVDB occupancy map and writes OUT/map.vdb, OUT/map_mesh.ply, OUT/map_points.ply.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <map>

#include "apps/command.h"
#include "apps/progress_bar.h"
#include "core/error.h"
#include "mapping/map_io.h"
#include "mapping/projective_integrator.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/png_io.h"
#include "pipeline/dataset/trajectory_tum.h"

namespace pensight::app {
int cmd_map(const Args& args) {
  CLI::App cli(
      "Integrate a dataset's depth images and camera poses into the occupancy map (OpenVDB) and "
      "write OUT/map.vdb, OUT/map_mesh.ply and OUT/map_points.ply. Depth: OUT/depth/ (pensight "
      "run's dense depth) and poses: OUT/trajectory_tum.txt, or with --from-truth the dataset's "
      "groundtruth0 depth and poses.",
      "pensight map");
  std::string dataset_dir, out_dir, config_file;
  bool from_truth = false, quiet = false;
  cli.add_option("DATASET", dataset_dir, "dataset folder")->required();
  cli.add_option("--out", out_dir, "output folder (also where pensight run wrote its outputs)")
      ->required();
  cli.add_flag(
      "--from-truth", from_truth,
      "use groundtruth0/depth/ and groundtruth0/data.csv instead of pensight run's output");
  cli.add_option("--config", config_file, "map YAML (docs/mapping.md); default: built-in values");
  cli.add_flag("--quiet", quiet, "no progress bar");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }

  const mapping::MapConfig config =
      config_file.empty() ? mapping::MapConfig{} : mapping::read_map_config(config_file);
  const Dataset dataset = read_dataset(dataset_dir);
  const std::filesystem::path out(out_dir);
  std::map<int64_t, Eigen::Isometry3d> body_poses;
  if (from_truth) {
    if (!dataset.groundtruth0 || !dataset.groundtruth0->has_depth) {
      throw Error(
          "'" + dataset_dir +
          "' has no groundtruth0/depth/: --from-truth needs a rendered or surveyed dataset");
    }
    for (const GroundTruthRow& r : dataset.groundtruth0->rows) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = rotation_from_rpy(r.roll_rad, r.pitch_rad, r.yaw_rad);
      T.translation() = r.p_pen_body_m;
      body_poses[r.timestamp_ns] = T;
    }
  } else {
    const std::filesystem::path trajectory = out / kTrajectoryTumFile;
    if (!std::filesystem::is_directory(out / "depth") || !std::filesystem::exists(trajectory)) {
      throw Error("'" + out_dir + "' has no depth/ folder or no " + kTrajectoryTumFile +
                  ": run `pensight run DATASET --out " + out_dir +
                  "` with the depth model first, or map the ground truth with --from-truth");
    }
    for (const TumPose& p : read_trajectory_tum(trajectory)) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = p.q.normalized().toRotationMatrix();
      T.translation() = p.p_m;
      body_poses[p.timestamp_ns] = T;
    }
  }

  std::filesystem::create_directories(out);
  mapping::OccupancyMap map(config);
  mapping::ProjectiveIntegrator integrator(dataset.cam0.camera, config);
  ProgressBar bar("map");
  size_t integrated = 0, without_pose = 0, without_depth = 0;
  double total_ms = 0, max_ms = 0;
  for (size_t i = 0; i < dataset.frames.size(); ++i) {
    if (!quiet) bar.update(i, dataset.frames.size());
    const auto pose = body_poses.find(dataset.frames[i].timestamp_ns);
    if (pose == body_poses.end() || !pose->second.matrix().allFinite()) {
      ++without_pose;
      continue;
    }
    const std::filesystem::path depth_file = out / "depth" / dataset.frames[i].filename;
    if (!from_truth && !std::filesystem::exists(depth_file)) {
      ++without_depth;
      continue;
    }
    const ImageF32 depth =
        from_truth ? dataset.load_depth_m(i)
                   : depth_m_from_mm(read_png_u16(depth_file, dataset.cam0.camera.width_px,
                                                  dataset.cam0.camera.height_px));
    const auto t0 = std::chrono::steady_clock::now();
    integrator.integrate(map, depth, pose->second * dataset.cam0.T_body_camera);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    total_ms += ms;
    max_ms = std::max(max_ms, ms);
    ++integrated;
  }
  if (!quiet) bar.update(dataset.frames.size(), dataset.frames.size());

  const mapping::SurfaceMesh mesh = mapping::write_map_outputs(map, out);
  std::printf("frames: %zu integrated, %zu without a pose, %zu without depth\n", integrated,
              without_pose, without_depth);
  std::printf("integration: mean %.1f ms, max %.1f ms per frame at %.0f mm voxels\n",
              integrated ? total_ms / static_cast<double>(integrated) : 0.0, max_ms,
              config.voxel_m * 1e3);
  std::printf("map: %zu occupied voxels, %.1f MB in memory, map.vdb %.1f MB; mesh %zu vertices\n",
              map.occupied_voxel_count(), static_cast<double>(map.memory_bytes()) / 1e6,
              static_cast<double>(std::filesystem::file_size(out / "map.vdb")) / 1e6,
              mesh.vertices.size());
  std::printf("wrote %s/map.vdb, map_mesh.ply, map_points.ply\n", out_dir.c_str());
  return integrated > 0 ? 0 : 1;
}

PENSIGHT_COMMAND("map", "integrate depth and poses into the OpenVDB occupancy map", cmd_map);

}  // namespace pensight::app
