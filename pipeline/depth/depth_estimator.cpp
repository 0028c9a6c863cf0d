#include "pipeline/depth/depth_estimator.h"

#include <limits>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/file_bytes.h"
#include "core/threads.h"
#include "core/timing.h"
#include "kernels/nn/nn.h"
#include "kernels/nn/nn_onnx.h"
#include "kernels/sparse_prior/sparse_prior.h"
#include "pipeline/depth/depth_input.h"
#include "pipeline/depth/prior_surface.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_context.h"
#include "runtime/vk_stream.h"

namespace pensight {

namespace {

constexpr EnumName<CpuInference> kCpuInferenceNames[] = {
    {CpuInference::kAuto, "auto"},
    {CpuInference::kOpenCv, "opencv"},
    {CpuInference::kEngine, "engine"},
};

}  // namespace

const char* to_string(CpuInference inference) {
  return enum_name<CpuInference>(kCpuInferenceNames, inference);
}

CpuInference parse_cpu_inference(const std::string& name) {
  if (const auto i = parse_enum_name<CpuInference>(kCpuInferenceNames, name)) return *i;
  throw Error("unknown CPU inference '" + name + "'; use " +
              enum_choices<CpuInference>(kCpuInferenceNames));
}

namespace {

struct ContractShape {
  int width = 0, height = 0;
  int prior_channels = 2;  // S1, S2 and, with 3, the prior surface Q
};

// Checks the model against the contract and returns its input shape.
ContractShape contract_shape(const kernels::Graph& g, const std::string& file) {
  auto fail = [&](const std::string& what) {
    throw Error(file + " is not a depth network: " + what +
                " (expected inputs image [1,1,H,W] and prior [1,2,H,W] or [1,3,H,W], output "
                "depth [1,1,H,W]; see models/README.md)");
  };
  if (g.inputs().size() != 2 || g.outputs().size() != 1) {
    fail(std::to_string(g.inputs().size()) + " inputs and " + std::to_string(g.outputs().size()) +
         " outputs");
  }
  const kernels::Value& image = g.value(g.inputs()[0]);
  const kernels::Value& prior = g.value(g.inputs()[1]);
  const kernels::Value& depth = g.value(g.outputs()[0]);
  if (image.name != "image" || prior.name != "prior") {
    fail("inputs named '" + image.name + "' and '" + prior.name + "'");
  }
  auto is = [](const kernels::Dims& d, int64_t c, int64_t h, int64_t w) {
    return d.size() == 4 && d[0] == 1 && d[1] == c && d[2] == h && d[3] == w;
  };
  if (image.shape.size() != 4) fail("image has rank " + std::to_string(image.shape.size()));
  const int64_t h = image.shape[2], w = image.shape[3];
  const int64_t c = prior.shape.size() == 4 ? prior.shape[1] : 0;
  if (!is(image.shape, 1, h, w) || (c != 2 && c != 3) || !is(prior.shape, c, h, w) ||
      !is(depth.shape, 1, h, w) || h < 16 || w < 16) {
    fail("shapes do not match");
  }
  return {static_cast<int>(w), static_cast<int>(h), static_cast<int>(c)};
}

cv::Mat as_mat(std::vector<float>& data, std::initializer_list<int> dims) {
  std::vector<int> d(dims);
  return cv::Mat(static_cast<int>(d.size()), d.data(), CV_32F, data.data());
}

// The Vulkan path: S1/S2 recorded straight into the network's prior input, then the graph.
struct VulkanNet {
  kernels::VkModel model;
  kernels::SparsePriorVk prior;
  vk::TypedBuffer<kernels::SparsePoint> points;
  vk::TypedBuffer<kernels::SparsePriorParams> params;
  vk::CommandStream stream;

  VulkanNet(vk::Context& ctx, const kernels::Graph& g, const kernels::SparsePriorShape& shape)
      : model(ctx, g, {.fp16_storage = false}),
        prior(ctx, shape),
        points(ctx, kernels::kMaxSparsePoints),
        params(ctx, 1),
        stream(ctx) {
    prior.record(stream, points.raw(), params, model.input_buffer(1));
    model.record(stream);
  }
};

}  // namespace

struct DepthEstimator::Impl {
  PinholeCamera camera;
  NetworkView view;  // the part of the camera image the network sees
  DepthEstimatorConfig config;
  kernels::Graph graph;
  kernels::SparsePriorShape shape;
  int prior_channels = 2;
  Backend backend = Backend::kCpu;
  CpuInference inference = CpuInference::kEngine;  // on the CPU backend
  int threads = 1;
  std::optional<cv::dnn::Net> opencv;
  std::unique_ptr<VulkanNet> vulkan;
  std::string device_name;
  std::optional<PixelRays> rays;  // of the view scaled to the network's grid
  NetWallShape wall;              // for the prior surface, in the network's pixels

  // Network output (H x W, metres) for one frame.
  // depths: the priors in the network's pixels; points: the same without their quality.
  std::vector<float> run(const ImageU8& small, std::span<const SparseDepth> depths,
                         std::span<const kernels::SparsePoint> points) {
    const size_t n = static_cast<size_t>(shape.width) * shape.height;
    std::vector<float> image(n);
    std::transform(small.pixels.begin(), small.pixels.end(), image.begin(),
                   [](uint8_t v) { return v / 255.0f; });
    std::optional<PriorSurface> surface;
    if (prior_channels == 3) surface = fit_prior_surface(depths, shape.width, shape.height, wall);
    if (vulkan) {
      vulkan->model.input_buffer(0).upload(image.data(), n * sizeof(float));
      if (surface) {
        std::vector<float> q(n);
        render_prior_surface(*surface, q);
        vulkan->model.input_buffer(1).upload(q.data(), n * sizeof(float), 2 * n * sizeof(float));
      }
      vulkan->points.upload(points);
      vulkan->params.fill({static_cast<uint32_t>(points.size())});
      vulkan->stream.submit_and_wait();
      std::vector<float> out(n);
      vulkan->model.output_buffer(0).download(out.data(), n * sizeof(float));
      return out;
    }
    std::vector<float> prior(prior_channels * n);
    kernels::sparse_prior_cpu(shape, points, prior);
    if (surface) render_prior_surface(*surface, std::span<float>(prior).subspan(2 * n));
    if (opencv) {
      opencv->setInput(as_mat(image, {1, 1, shape.height, shape.width}), "image");
      opencv->setInput(as_mat(prior, {1, prior_channels, shape.height, shape.width}), "prior");
      const cv::Mat out = opencv->forward("depth");
      const cv::Mat flat = out.isContinuous() ? out : out.clone();
      return std::vector<float>(flat.ptr<float>(), flat.ptr<float>() + n);
    }
    const kernels::Tensor inputs[] = {
        {{1, 1, shape.height, shape.width}, std::move(image)},
        {{1, prior_channels, shape.height, shape.width}, std::move(prior)}};
    return std::move(kernels::run_cpu(graph, inputs)[0].data);
  }
};

DepthEstimator::DepthEstimator(const PinholeCamera& camera, const DepthEstimatorConfig& config,
                               Device& device)
    : impl_(std::make_unique<Impl>()) {
  validate(config);
  Impl& m = *impl_;
  m.camera = camera;
  m.config = config;
  const std::string file = config.model.string();
  const std::optional<std::string> bytes = read_file_bytes(config.model);
  if (!bytes) {
    throw Error("cannot read the depth model " + file +
                ": check the path (models/README.md lists the shipped models) or run with "
                "--no-depth");
  }
  m.graph = kernels::import_onnx_bytes(*bytes, file);
  const auto [w, h, prior_channels] = contract_shape(m.graph, file);
  m.shape = {w, h, config.sigma_px};
  m.prior_channels = prior_channels;
  // A camera of another aspect: the network runs on the centred crop of its own aspect.
  m.view = network_view(camera.width_px, camera.height_px, w, h);
  const PinholeCamera seen = network_camera(camera, m.view, w, h);
  m.rays.emplace(seen);
  m.wall = {.curvature_per_m = config.net_curvature_per_m, .focal_px = seen.fx_px};
  m.threads = worker_threads(config.cpu_threads);

  auto make_opencv = [&]() -> bool {
    try {
      const std::string compatible = kernels::opencv_dnn_compatible(*bytes);
      m.opencv = cv::dnn::readNetFromONNX(compatible.data(), compatible.size());
      cv::setNumThreads(m.threads);
      m.inference = CpuInference::kOpenCv;
      return true;
    } catch (const cv::Exception& e) {
      if (config.cpu_inference == CpuInference::kOpenCv) {
        throw Error("OpenCV DNN cannot read " + file + " (" + e.msg +
                    "); use --depth-cpu-inference engine");
      }
      return false;
    }
  };
  switch (choose_backend(config.backend, device, {})) {
    case Backend::kVulkan: {
      vk::Context& ctx = device.vulkan();
      m.vulkan = std::make_unique<VulkanNet>(ctx, m.graph, m.shape);
      m.device_name = ctx.info().name;
      m.backend = Backend::kVulkan;
      break;
    }
    case Backend::kCuda:
      throw Error("the depth stage has no CUDA path; use --depth-backend vulkan or cpu");
    case Backend::kCpu:
    case Backend::kAuto:
      m.backend = Backend::kCpu;
      if (config.cpu_inference == CpuInference::kEngine || !make_opencv()) {
        m.inference = CpuInference::kEngine;
      }
      break;
  }
}

DepthEstimator::~DepthEstimator() = default;
DepthEstimator::DepthEstimator(DepthEstimator&&) noexcept = default;
DepthEstimator& DepthEstimator::operator=(DepthEstimator&&) noexcept = default;

Backend DepthEstimator::backend() const {
  return impl_->backend;
}

CpuInference DepthEstimator::cpu_inference() const {
  return impl_->inference;
}

double DepthEstimator::gflop() const {
  return impl_->graph.flops() * 1e-9;
}

std::string DepthEstimator::description() const {
  const Impl& m = *impl_;
  char flops[32];
  std::snprintf(flops, sizeof flops, "%.2f GFLOP", gflop());
  std::string where;
  if (m.backend == Backend::kVulkan) {
    where = "vulkan (" + m.device_name + ")";
  } else if (m.inference == CpuInference::kOpenCv) {
    where = "opencv dnn (" + std::to_string(m.threads) + " threads)";
  } else {
    where = "engine cpu";
  }
  return where + ", " + std::to_string(m.shape.width) + "x" + std::to_string(m.shape.height) +
         ", " + flops;
}

DenseDepth DepthEstimator::estimate(const ImageU8& image, std::span<const SparseDepth> priors) {
  Impl& m = *impl_;
  check_image_size(image.width, image.height, m.camera, "depth stage", "image",
                   " (the resolution of cam0/sensor.yaml)");
  DenseDepth out;
  if (priors.empty()) {
    out.reason = "no sparse depths (the FFT pose is NaN)";
    out.pose.reason = out.reason;
    return out;
  }
  Stopwatch sw;
  const ImageU8 small = network_image(image, m.view, m.shape.width, m.shape.height);
  const std::vector<SparseDepth> depths =
      network_depths(priors, m.view, m.shape.width, m.shape.height);
  if (depths.empty()) {
    out.reason = "no sparse depths in the network's view of the frame";
    out.pose.reason = out.reason;
    return out;
  }
  const std::vector<kernels::SparsePoint> points = points_of(depths);
  kernels::validate(m.shape, points);
  std::vector<float> net = m.run(small, depths, points);
  // SILog weighs a common scale error lightly (0.15 of its variance term), and a network trained
  // on many pens carries their average curvature into a frame whose priors say otherwise: both
  // are smooth over the image, so a surface through the ratios prior / network takes them out.
  align_to_priors(net, m.shape.width, m.shape.height, depths);
  // The pose comes from the network's own grid (every pixel it estimated, none interpolated).
  ImageF32 small_depth(m.shape.width, m.shape.height);
  small_depth.pixels = std::move(net);
  // Outside the view (a camera of another aspect): NaN, no depth.
  out.depth_m = ImageF32(image.width, image.height, std::numeric_limits<float>::quiet_NaN());
  const cv::Mat src(small_depth.height, small_depth.width, CV_32F, small_depth.pixels.data());
  cv::Mat whole(out.depth_m.height, out.depth_m.width, CV_32F, out.depth_m.pixels.data());
  cv::Mat dst = whole(cv::Rect(m.view.x0_px, m.view.y0_px, m.view.width_px, m.view.height_px));
  cv::resize(src, dst, dst.size(), 0, 0, cv::INTER_LINEAR);
  out.network_ms = sw.elapsed_ms();
  sw.restart();
  out.pose = depth_plane_pose(small_depth, *m.rays, m.config.plane);
  out.pose_ms = sw.elapsed_ms();
  return out;
}

}  // namespace pensight
