#include "pipeline/fft/net_detector.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/error.h"
#include "core/threads.h"
#include "core/timing.h"
#include "pipeline/fft/fine_mesh_probe.h"
#include "pipeline/fft/grid_plan.h"
#include "pipeline/fft/lattice_chirp.h"
#include "pipeline/fft/net_detector_params.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_stream.h"

namespace pensight {

namespace {

// The Vulkan stage with its buffers and the command stream recorded once.
struct VulkanStage {
  vk::Context& ctx;
  std::optional<kernels::FftRoiVk> kernel;
  std::optional<vk::Buffer> image, rois, samples, spectrum;
  std::optional<vk::TypedBuffer<kernels::RoiLattice>> lattices;
  std::unique_ptr<vk::CommandStream> stream;

  VulkanStage(vk::Context& context, const kernels::FftRoiShape& shape,
              const kernels::PeakParams& peaks, const std::vector<kernels::RoiOrigin>& origins)
      : ctx(context) {
    kernel.emplace(ctx, shape, peaks);
    const auto n = static_cast<uint32_t>(origins.size());
    image.emplace(ctx, kernel->image_bytes());
    rois.emplace(ctx, origins.size() * sizeof(kernels::RoiOrigin));
    rois->upload(origins.data(), origins.size() * sizeof(kernels::RoiOrigin));
    samples.emplace(ctx, kernel->samples_bytes(n));
    spectrum.emplace(ctx, kernel->spectrum_bytes(n));
    lattices.emplace(ctx, origins.size(), vk::MemoryUsage::kReadback);
    stream = std::make_unique<vk::CommandStream>(ctx);
    kernel->record(*stream, *image, *rois, *samples, *spectrum, lattices->raw(), n);
  }

  std::vector<kernels::RoiLattice> run(const ImageU8& frame) {
    image->upload(frame.pixels.data(), frame.pixels.size());
    stream->submit_and_wait();
    return lattices->to_vector();
  }
};

constexpr int kMeshAngleRounds = 3;
constexpr double kMeshAngleSettled_rad = 0.0035;  // 0.2 deg: a range change below 0.2 %
// The chirp correction is computed on the fitted plane, so where it moves that plane it is made
// again on the new one: a plane off by a few degrees on a steep frame (few ROIs, 45-50 deg)
// under-corrects by a few percent of range. Frontal frames move < 0.1 deg and stop at one step.
constexpr int kChirpRounds = 3;
constexpr double kChirpSettled_rad = 0.0087;  // 0.5 deg

}  // namespace

struct NetDetector::Impl {
  PinholeCamera camera;
  NetDetectorConfig config;
  kernels::FftRoiShape shape;
  std::vector<kernels::RoiOrigin> rois;
  Backend backend = Backend::kCpu;
  std::string description;
  std::optional<kernels::FftRoiCpu> cpu;
  std::optional<VulkanStage> vulkan;
  std::optional<FineMeshProbe> fine_mesh;
  // Native ROIs of the FFT's side for frames whose mesh the planned ROIs cannot hold; made on the
  // first such frame. It has no probe of its own (its ROIs are not resampled).
  std::unique_ptr<NetDetector> native;
  Device* native_device = nullptr;
  MeshAngleFilter mesh_filter{std::nullopt};
  TexturePatch previous_patch;  // the previous frame's, for NetDetection::texture

  // Per point, the normal of the pose's net surface there.
  static std::vector<Eigen::Vector3d> normals_on(const FftRelativePose& pose,
                                                 std::span<const RoiNetPoint> points) {
    std::vector<Eigen::Vector3d> normals;
    normals.reserve(points.size());
    for (const RoiNetPoint& p : points)
      normals.push_back(net_surface_normal(pose.surface_C, p.p_C));
    return normals;
  }

  // Net points of every ROI's lattice for a cell of the given opening angle.
  std::vector<RoiNetPoint> model_points(const std::vector<kernels::RoiLattice>& lattices,
                                        double opening_angle_rad,
                                        const Eigen::Vector3d* normal) const {
    std::vector<RoiNetPoint> points;
    points.reserve(rois.size());
    const MeshModel mesh{config.bar_length_m, opening_angle_rad};
    for (size_t i = 0; i < rois.size(); ++i) {
      points.push_back(roi_net_point(lattices[i], rois[i], shape.roi_size_px, camera, mesh,
                                     config.points, normal));
    }
    return points;
  }

  // The valid ROIs' lattices corrected for their chirp on the plane of `pose`, the opening angle
  // measured again from them (the chirp biases the bars' angle as it does their length: up to
  // 3 deg on a frame 30 deg oblique), their points and the pose again. The first fit stays where
  // the second loses the plane. Returns the angle the plane's normal moved by (0 when it stays).
  double correct_chirp(NetDetection& d, MeshAngleFilter& filter) const {
    const Eigen::Vector3d normal =
        net_plane_normal(std::tan(d.pose.psi_net_rad), std::tan(d.pose.pitch_net_rad));
    const ChirpModelParams model{.window = shape.window,
                                 .subbin = config.peaks.subbin,
                                 .resampled = shape.roi_size_px != shape.fft_size};
    std::vector<kernels::RoiLattice> corrected = d.lattices;
    for (size_t i = 0; i < rois.size(); ++i) {
      if (!d.points[i].valid()) continue;
      corrected[i] = chirp_corrected(d.lattices[i], rois[i], shape.roi_size_px,
                                     d.points[i].centre_px, camera, normal, model);
    }
    std::vector<RoiNetPoint> points = model_points(corrected, filter.angle_rad(), &normal);
    if (d.mesh_angle_frame.valid()) {  // the filter took this frame's measurement: refine it
      const MeshAngleMeasurement angle =
          measure_mesh_angle(points, d.pose.inlier, normals_on(d.pose, points), camera,
                             config.mesh_type, config.mesh_angle);
      if (angle.valid()) {
        d.mesh_angle_frame = angle;
        points = model_points(corrected, filter.refine(angle), &normal);
      }
    }
    FftRelativePose pose = relative_pose_fft(points, config.pose);
    if (!pose.valid()) return 0;
    const Eigen::Vector3d moved =
        net_plane_normal(std::tan(pose.psi_net_rad), std::tan(pose.pitch_net_rad));
    d.points = std::move(points);
    d.pose = std::move(pose);
    return std::acos(std::min(1.0, moved.dot(normal)));  // both unit, towards the camera
  }

  // The frame's points, opening angle and pose from its lattices, modelled with `filter`'s angle
  // and updating it.
  void solve(NetDetection& d, MeshAngleFilter& filter) const {
    d.mesh_angle_frame = {};
    d.points = model_points(d.lattices, filter.angle_rad(), nullptr);
    // Rounds of plane from the points alone -> opening angle -> points, until the angle settles:
    // one for an angle already known, two or three from a prior 10-30 deg off (the first plane
    // is then tilted by the wrong cell's range errors).
    RelativePoseFftParams plane_only = config.pose;
    plane_only.check_tilts = false;
    plane_only.fuse_roi_tilt = false;
    double modelled = filter.angle_rad();
    for (int round = 0; round < kMeshAngleRounds; ++round) {
      const FftRelativePose plane = relative_pose_fft(d.points, plane_only);
      if (!plane.valid()) break;
      const Eigen::Vector3d normal =
          net_plane_normal(std::tan(plane.psi_net_rad), std::tan(plane.pitch_net_rad));
      d.mesh_angle_frame = measure_mesh_angle(d.points, plane.inlier, normals_on(plane, d.points),
                                              camera, config.mesh_type, config.mesh_angle);
      if (!d.mesh_angle_frame.valid()) break;
      const double angle =
          round == 0 ? filter.update(d.mesh_angle_frame) : filter.refine(d.mesh_angle_frame);
      d.points = model_points(d.lattices, angle, &normal);
      if (std::abs(angle - modelled) < kMeshAngleSettled_rad) break;
      modelled = angle;
    }
    d.pose = relative_pose_fft(d.points, config.pose);
    if (!config.chirp_correction || !d.pose.valid()) return;
    for (int round = 0; round < kChirpRounds; ++round) {
      if (correct_chirp(d, filter) < kChirpSettled_rad) break;
    }
  }

#if PENSIGHT_HAS_CUDA
  std::optional<kernels::FftRoiCuda> cuda;
#endif

  void make_cpu() {
    const int threads = worker_threads(config.cpu_threads);
    cpu.emplace(shape, config.peaks, threads);
    backend = Backend::kCpu;
    description = "cpu (FFTW, " + std::to_string(threads) + " threads)";
  }

  void make_vulkan(vk::Context& ctx) {
    description = "vulkan (" + ctx.info().name + ")";
    vulkan.emplace(ctx, shape, config.peaks, rois);
    backend = Backend::kVulkan;
  }

  void make_cuda() {
#if PENSIGHT_HAS_CUDA
    cuda.emplace(shape, config.peaks, static_cast<int>(rois.size()));
    backend = Backend::kCuda;
    description = "cuda (cuFFT)";
#else
    throw Error(
        "backend cuda: this build has no CUDA path; rebuild with -DPENSIGHT_CUDA=ON or "
        "use --backend vulkan or cpu");
#endif
  }

  void choose(Device& device) {
    switch (choose_backend(config.backend, device, {.cuda = PENSIGHT_HAS_CUDA != 0})) {
      case Backend::kVulkan:
        return make_vulkan(device.vulkan());
      case Backend::kCuda:
        return make_cuda();
      case Backend::kCpu:
      case Backend::kAuto:
        return make_cpu();
    }
  }

  // The frame read on this detector's own grid: lattices, pose (the carried opening angle as a
  // prior) and depth priors; no texture step.
  NetDetection detect_on_grid(const ImageU8& image, int64_t timestamp_ns) {
    NetDetection d;
    d.timestamp_ns = timestamp_ns;
    d.rois = rois;
    d.roi_size_px = shape.roi_size_px;
    Stopwatch sw;
    switch (backend) {
      case Backend::kVulkan:
        d.lattices = vulkan->run(image);
        break;
#if PENSIGHT_HAS_CUDA
      case Backend::kCuda:
        d.lattices = cuda->run(image, rois);
        break;
#endif
      default:
        d.lattices = cpu->run(image, rois);
        break;
    }
    d.fft_ms = sw.elapsed_ms();
    sw.restart();
    solve(d, mesh_filter);
    // The carried opening angle is a prior, never a gate: a frame that disagrees with it or that
    // it cannot explain (a new panel, a diamond section, another pen) is solved on its own, and
    // that solution replaces it.
    if ((!d.pose.valid() || mesh_filter.rejected_last()) && mesh_filter.has_estimate()) {
      MeshAngleFilter fresh(config.mesh_angle_rad, config.mesh_angle_filter);
      NetDetection alone = d;
      solve(alone, fresh);
      if (alone.pose.valid()) {
        d = std::move(alone);
        mesh_filter = fresh;
      }
    }
    if (mesh_filter.has_estimate()) d.mesh_angle_rad = mesh_filter.angle_rad();
    d.mesh_type = d.mesh_angle_frame.valid() ? d.mesh_angle_frame.type
                                             : config.mesh_type.value_or(MeshType::kSquare);
    for (const RoiNetPoint& p : d.points) d.reduced_rois += p.reduced ? 1 : 0;
    d.depths = roi_surface_priors(d.points, d.pose, config.grid.roi_size_px, camera, config.priors);
    d.pose_ms = sw.elapsed_ms();
    return d;
  }
};

NetDetector::NetDetector(const PinholeCamera& camera, const NetDetectorConfig& config,
                         Device& device)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.config = planned_detector_config(config, camera);
  validate(m.config);
  m.camera = camera;
  m.mesh_filter = MeshAngleFilter(m.config.mesh_angle_rad, m.config.mesh_angle_filter);
  m.rois = kernels::roi_grid(camera.width_px, camera.height_px, m.config.grid);
  m.shape = {.width = camera.width_px,
             .height = camera.height_px,
             .roi_size_px = m.config.grid.roi_size_px,
             .fft_size = m.config.fft_size,
             .window = m.config.window};
  m.choose(device);
  m.fine_mesh.emplace(m.shape, m.config.peaks, m.config.points.min_quality);
  m.native_device = &device;
  // The planned grid is part of what a user needs to read a run (grid_plan.h).
  m.description += ", " + std::to_string(m.config.grid.rows) + "x" +
                   std::to_string(m.config.grid.cols) + " ROIs of " +
                   std::to_string(m.config.grid.roi_size_px) + " px, FFT " +
                   std::to_string(m.config.fft_size);
}

NetDetector::~NetDetector() = default;
NetDetector::NetDetector(NetDetector&&) noexcept = default;
NetDetector& NetDetector::operator=(NetDetector&&) noexcept = default;

Backend NetDetector::backend() const {
  return impl_->backend;
}
std::string NetDetector::description() const {
  return impl_->description;
}
const std::vector<kernels::RoiOrigin>& NetDetector::rois() const {
  return impl_->rois;
}
const NetDetectorConfig& NetDetector::config() const {
  return impl_->config;
}

NetDetection NetDetector::detect(const ImageU8& image, int64_t timestamp_ns) {
  Impl& m = *impl_;
  check_image_size(image.width, image.height, m.camera, "NetDetector", "image",
                   " (the resolution of cam0/sensor.yaml)");
  Stopwatch sw;
  NetDetection d;
  if (std::optional<std::string> why = m.fine_mesh->too_fine(image)) {
    // The planned grid would read aliases, or leave its band's low end to fouling patches and
    // the like: the frame is analysed on native ROIs instead, and its reason names both where
    // those give no pose either.
    const double probe_ms = sw.elapsed_ms();
    if (!m.native) {
      NetDetectorConfig native = m.config;
      native.grid.roi_size_px = m.config.fft_size;
      native.texture.enabled = false;  // the step is this detector's, whichever grid read a frame
      m.native = std::make_unique<NetDetector>(m.camera, native, *m.native_device);
    }
    d = m.native->detect(image, timestamp_ns);
    d.pose_ms += probe_ms;
    if (!d.pose.valid()) d.pose.reason = *why + "; on those: " + d.pose.reason;
  } else {
    const double probe_ms = sw.elapsed_ms();
    d = m.detect_on_grid(image, timestamp_ns);
    d.pose_ms += probe_ms;
  }
  if (m.config.texture.enabled) {
    sw.restart();
    TexturePatch patch = texture_patch(image, m.camera, timestamp_ns, m.config.texture);
    d.texture = texture_step(m.previous_patch, patch, d.points, d.pose, m.camera,
                             m.config.bar_length_m, m.config.texture);
    m.previous_patch = std::move(patch);
    d.pose_ms += sw.elapsed_ms();
  }
  return d;
}

}  // namespace pensight
