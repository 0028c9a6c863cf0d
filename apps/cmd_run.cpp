#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>

#include "apps/bag_input.h"
#include "apps/command.h"
#include "apps/default_model.h"
#include "apps/progress_bar.h"
#include "core/error.h"
#include "core/log.h"
#include "pipeline/dataset/diagnostics_csv.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "pipeline/dataset/trajectory_tum.h"
#include "tools/runner.h"
#if PENSIGHT_HAS_MAPPING
#include "mapping/map_io.h"
#include "mapping/mapping_stage.h"
#endif

namespace pensight::app {

int cmd_run(const Args& args) {
  CLI::App cli(
      "Run the pipeline on a dataset (../shared/dataset-format.md layout) or a ROS 1 bag "
      "(BAG.bag, converted as by bag-to-dataset: docs/ros.md) and write OUT/estimates.csv",
      "pensight run");
  std::string dataset_dir, out_dir, backend = "auto";
  bool quiet = false;
  RunOptions options;
  kernels::RoiGrid& grid = options.detector.grid;
  cli.add_option("DATASET", dataset_dir, "dataset folder, or a ROS 1 bag (*.bag)")->required();
  cli.add_option("--out", out_dir, "output folder")->required();
  cli.add_option("--backend", backend,
                 "auto|cpu|vulkan|cuda (auto: a real GPU if there is one, else the CPU path)")
      ->capture_default_str();
  cli.add_option("--roi-rows", grid.rows, "ROI grid rows")->capture_default_str();
  cli.add_option("--roi-cols", grid.cols, "ROI grid columns")->capture_default_str();
  cli.add_option("--roi-size", grid.roi_size_px,
                 "ROI side in pixels (0: from the camera's focal length and the bar length, "
                 "300 at fx 462 px and 30 mm; docs/fft_detection.md)")
      ->capture_default_str();
  cli.add_option("--roi-border", grid.border_px, "margin kept free at the image edges, pixels")
      ->capture_default_str();
  cli.add_option("--fft-size", options.detector.fft_size,
                 "resampled ROI side (power of two; 0: the largest up to min(ROI, 256))")
      ->capture_default_str();
  cli.add_option("--cpu-threads", options.detector.cpu_threads, "CPU path threads (0: all)")
      ->capture_default_str();
  bool no_published = false;
  cli.add_flag("--no-published", no_published,
               "do not run the published global-pose node (OUT/global_pose_published.csv)");
  bool no_net_texture = false;
  cli.add_flag("--no-net-texture", no_net_texture,
               "do not measure the net texture's move at the image centre (the global pose's "
               "along-net odometry, docs/global_pose.md)");
  cli.add_flag("--realtime", options.realtime,
               "push each sample at its timestamp (the timing a vehicle sees) instead of as fast "
               "as possible");
  cli.add_flag("--overlays", options.overlays,
               "write OUT/overlays/<frame>.png for every frame (ROI grid, lattices, pose); "
               "without it, for 4 frames the report shows");
  cli.add_flag("--quiet", quiet, "no progress bar");
  std::string model, depth_backend = "auto", depth_cpu_inference = "auto";
  bool no_depth = false;
  cli.add_option("--model", model,
                 "depth network (ONNX, models/README.md); default: the shipped one that sees "
                 "most of the frame (models/compact_depth*.onnx; another aspect: the centred "
                 "crop), where it is found");
  cli.add_flag("--no-depth", no_depth, "do not run the dense-depth stage");
  bool no_dvl_scale = false;
  cli.add_flag("--no-dvl-scale", no_dvl_scale,
               "keep scene.yaml's bar length for dense depth even where the DVL's beam ranges "
               "measure another (docs/dense_depth.md)");
  bool no_dvl_tilt = false;
  cli.add_flag("--no-dvl-tilt", no_dvl_tilt,
               "keep the camera's net tilt for dense depth even where the DVL's beam ranges "
               "measure another (docs/dense_depth.md)");
  cli.add_option("--depth-backend", depth_backend, "auto|cpu|vulkan (auto: vulkan on a real GPU)")
      ->capture_default_str();
  cli.add_option("--depth-cpu-inference", depth_cpu_inference,
                 "auto|opencv|engine: the network's library on the cpu backend (auto: OpenCV DNN "
                 "where it reads the model)")
      ->capture_default_str();
  BagInputOptions bag_options;
  add_bag_options(cli, bag_options);
#if PENSIGHT_HAS_MAPPING
  bool map = false;
  std::string map_config_file;
  cli.add_flag("--map", map,
               "run the mapping stage: the dense-depth stage's depth (with --no-depth or no model: "
               "the dataset's ground-truth depth, groundtruth0/depth/) at the estimated camera "
               "poses; writes OUT/map.vdb, map_mesh.ply, map_points.ply");
  cli.add_option("--map-config", map_config_file, "map YAML (docs/mapping.md)");
#endif
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }

  options.detector.backend = parse_backend(backend);
  options.write_published_global_pose = !no_published;
  options.detector.texture.enabled = !no_net_texture;
  ProgressBar bar("run");
  if (!quiet) options.on_progress = [&](size_t done, size_t total) { bar.update(done, total); };
  // A bag runs as the dataset it converts to, so every output is that of a dataset folder.
  std::optional<ConvertedBag> bag;
  if (is_bag_file(dataset_dir)) {
    bag.emplace(dataset_dir, out_dir, bag_options, quiet);
    options.input = dataset_dir;
  } else if (any_bag_option_given(bag_options)) {
    throw Error(
        "--scene, --camera, --dvl-sensor, --topics, --water-density and "
        "--surface-pressure are for a bag input (*.bag); '" +
        dataset_dir + "' is a dataset folder, whose own files give them");
  }
  const Dataset dataset =
      read_dataset(bag ? bag->dataset_dir() : std::filesystem::path(dataset_dir));
  options.dvl_depth_scale = !no_dvl_scale;
  options.dvl_net_tilt = !no_dvl_tilt;
  if (!no_depth) {
    const std::filesystem::path file = model.empty() ? find_default_depth_model(dataset.cam0.camera)
                                                     : std::filesystem::path(model);
    if (!file.empty()) {
      options.depth =
          DepthEstimatorConfig{.model = file,
                               .backend = parse_backend(depth_backend),
                               .cpu_inference = parse_cpu_inference(depth_cpu_inference),
                               .cpu_threads = options.detector.cpu_threads};
    } else {
      log_info(
          "no depth model in models/ (compact_depth*.onnx): the dense-depth stage is off; "
          "give one with --model");
    }
  }
#if PENSIGHT_HAS_MAPPING
  std::unique_ptr<mapping::MappingStage> mapper;
  if (map) {
    mapper = std::make_unique<mapping::MappingStage>(
        dataset.cam0.camera,
        map_config_file.empty() ? mapping::MapConfig{} : mapping::read_map_config(map_config_file));
    options.truth_depth = !options.depth;
    options.stages.push_back({[&](const FrameResult& r) { mapper->push(r); },
                              [&] {
                                mapper->finish();
                                mapping::write_map_outputs(mapper->map(), out_dir);
                                return mapper->stats();
                              }});
  }
#endif
  Device device;
  const RunSummary s = run_dataset(dataset, out_dir, options, device);
  std::printf("backend: %s\n", s.backend.c_str());
  if (!s.depth_backend.empty()) {
    std::printf("dense depth: %s; %zu frames with depth\n", s.depth_backend.c_str(),
                s.frames_with_depth);
  }
  std::printf("frames: %zu (%zu unreadable, %zu without a net pose)\n", s.frames, s.frames_skipped,
              s.frames_without_pose);
  std::printf("timing per node (%s; the published pipeline on a Jetson Orin beside it):\n%s",
              options.realtime ? "paced by the timestamps" : "as fast as possible",
              format_timing_table(s.timing).c_str());
  std::printf("global pose sensors:\n%s", s.global_pose_counters.c_str());
  std::printf("wrote %s/estimates.csv, %s, %s, %s, overlays/, %sreport.html\n", out_dir.c_str(),
              kDiagnosticsFile, kTrajectoryTumFile, kTimingFile, options.depth ? "depth/, " : "");
#if PENSIGHT_HAS_MAPPING
  if (mapper) {
    const mapping::MappingCounters c = mapper->counters();
    std::printf(
        "map: %zu frames integrated, %zu dropped (the stage fell behind), %zu without a pose, "
        "%zu without depth; %zu occupied voxels; wrote %s/map.vdb, map_mesh.ply, "
        "map_points.ply\n",
        c.integrated, c.dropped, c.without_pose, c.without_depth,
        mapper->map().occupied_voxel_count(), out_dir.c_str());
  }
#endif
  if (options.write_published_global_pose)
    std::printf("wrote %s/%s (published global-pose node, the baseline)\n", out_dir.c_str(),
                kPublishedGlobalPoseFile);
  return 0;
}

PENSIGHT_COMMAND("run", "run the pipeline on a dataset and write OUT/estimates.csv", cmd_run);

}  // namespace pensight::app
