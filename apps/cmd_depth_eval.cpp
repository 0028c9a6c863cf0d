// `pensight depth-eval DATASET... --model FILE`: the dense-depth stage's accuracy on rendered
// datasets against their ground truth, beside S1 alone and the FFT plane (depth_accuracy.h).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>

#include "apps/command.h"
#include "apps/default_model.h"
#include "core/error.h"
#include "core/units.h"
#include "pipeline/depth/depth_accuracy.h"
#include "tools/runner.h"

namespace pensight::app {

int cmd_depth_eval(const Args& args) {
  CLI::App cli(
      "Measures the dense-depth stage on rendered datasets (groundtruth0/depth/): AbsRel, "
      "delta < 1.25 and RMSE over the pixels that see the net, beside S1 alone and the FFT plane "
      "extrapolated to every pixel on the same frames, and the median d_net / psi_net error of the "
      "pose from dense depth. The network's depth carries the DVL's scale of the net's bar length "
      "and its tilt as in `pensight run` (dvl0/ with beam ranges; --no-dvl-scale, --no-dvl-tilt: "
      "without them). One Markdown table row per dataset.",
      "pensight depth-eval");
  std::vector<std::string> datasets;
  std::string model, backend = "auto", cpu_inference = "auto";
  size_t stride = 1;
  bool no_dvl_scale = false, no_dvl_tilt = false;
  cli.add_option("DATASET", datasets, "rendered dataset folders")->required();
  cli.add_option("--model", model, "depth network (default: the shipped one)");
  cli.add_option("--depth-backend", backend, "auto|cpu|vulkan (auto: vulkan on a real GPU)")
      ->capture_default_str();
  cli.add_option("--depth-cpu-inference", cpu_inference,
                 "auto|opencv|engine: the network's library on the cpu backend (auto: OpenCV DNN "
                 "where it reads the model)")
      ->capture_default_str();
  cli.add_option("--stride", stride, "every N-th frame")->check(CLI::Range(1, 1000));
  cli.add_flag("--no-dvl-scale", no_dvl_scale, "the network's depth without the DVL's scale");
  cli.add_flag("--no-dvl-tilt", no_dvl_tilt, "the network's depth without the DVL's tilt");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  std::printf(
      "| dataset | frames | AbsRel net | AbsRel S1 | AbsRel FFT plane | AbsRel prior surface | "
      "delta1 net | RMSE net m | d_net_depth median | psi_net_depth median deg | frames DVL-scaled "
      "| frames DVL-tilted |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  Device device;
  for (const std::string& dir : datasets) {
    const Dataset dataset = read_dataset(dir);
    NetDetector detector(dataset.cam0.camera, detector_config(dataset.scene), device);
    const std::filesystem::path file = model.empty() ? find_default_depth_model(dataset.cam0.camera)
                                                     : std::filesystem::path(model);
    if (file.empty()) {
      throw Error("no depth model in models/ (compact_depth*.onnx) for " + dir +
                  "; give one with --model");
    }
    DepthEstimator estimator(dataset.cam0.camera,
                             {.model = file,
                              .backend = parse_backend(backend),
                              .cpu_inference = parse_cpu_inference(cpu_inference),
                              .net_curvature_per_m = net_curvature_per_m(dataset.scene)},
                             device);
    std::optional<DvlDepthCorrection> dvl;
    if ((!no_dvl_scale || !no_dvl_tilt) && dataset.dvl0 && dataset.dvl0->has_beam_ranges) {
      dvl.emplace(dataset.cam0.camera, dataset.cam0.T_body_camera, dataset.dvl0->calibration,
                  no_dvl_scale ? std::nullopt : std::optional(DvlDepthScaleConfig{}),
                  no_dvl_tilt ? std::nullopt : std::optional(DvlNetTiltConfig{}));
    }
    const DepthAccuracy a =
        depth_accuracy(dataset, detector, estimator, stride, dvl ? &*dvl : nullptr);
    std::printf(
        "| %s | %zu | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.2f %% | %.2f | %zu | %zu |\n",
        std::filesystem::path(dir).filename().c_str(), a.frames, a.network.abs_rel, a.s1.abs_rel,
        a.fft_plane.abs_rel, a.surface.abs_rel, a.network.delta1, a.network.rmse_m,
        100 * a.d_net_median_rel, rad_to_deg(a.psi_median_rad), a.scaled_frames, a.tilted_frames);
    std::fflush(stdout);
  }
  return 0;
}

PENSIGHT_COMMAND("depth-eval", "dense-depth accuracy on rendered datasets (with baselines)",
                 cmd_depth_eval);

}  // namespace pensight::app
