#include "sim/depth_training.h"

#include <atomic>
#include <cmath>
#include <fstream>
#include <mutex>
#include <numeric>
#include <random>
#include <thread>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/threads.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/depth/depth_input.h"
#include "pipeline/fft/net_detector.h"
#include "runtime/device.h"
#include "sim/frame_state.h"
#include "sim/ground_truth.h"
#include "sim/render_cpu.h"
#include "tools/runner.h"

namespace pensight::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180;
constexpr double kCameraAhead_m =
    0.3;  // CameraConfig::position_B_m.x: the camera's lead on the body

class Draw {
 public:
  explicit Draw(uint64_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(rng_); }
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  bool chance(double p) { return uniform(0, 1) < p; }
  int integer(int lo, int hi) { return std::uniform_int_distribution<>(lo, hi)(rng_); }
  uint64_t bits() { return rng_(); }

 private:
  std::mt19937_64 rng_;
};

// The mesh is drawn so that its bar spans at least 5 px at the camera's distance: finer nets
// give the detector no lattice, hence no priors and no training sample.
void draw_net(Draw& d, NetConfig& net, double camera_to_net_m, double fx_px) {
  const double finest_m = std::max(0.015, 5 * camera_to_net_m / fx_px);
  net.bar_length_m = d.uniform(finest_m, std::max(0.045, 1.3 * finest_m));
  if (d.chance(0.6)) {
    net.mesh_type = MeshType::kSquare;
    net.opening_angle_deg = 90 + d.uniform(-12, 12);
  } else {
    net.mesh_type = MeshType::kDiamond;
    net.opening_angle_deg = d.uniform(60, 120);
  }
  net.opening_angle_variation_deg = d.uniform(0, 4);
  net.stretch_variation = d.uniform(0, 0.04);
  net.twine_width_m = net.bar_length_m * d.uniform(0.07, 0.22);
  net.knot_size_m = d.chance(0.2) ? 0 : net.bar_length_m * d.uniform(0.1, 0.3);
  net.knot_shape = d.chance(0.5) ? KnotShape::kSquare : KnotShape::kRound;
  net.albedo = d.uniform(0.3, 0.8);
  net.fouling = d.uniform(0, 0.7);
  net.fouling_coverage = d.chance(0.4) ? d.uniform(0, 0.5) : 0;
  if (d.chance(0.2)) net.ropes.spacing_m = d.uniform(1, 3);
  if (d.chance(0.15)) net.seam_spacing_m = d.uniform(1, 4);
}

// Turbidity up to where the net keeps e^-1.8 (17 %) of its contrast at the camera's distance:
// beyond it the net is not seen and the frame has no priors.
void draw_water_and_light(Draw& d, Scenario& s, double camera_to_net_m) {
  s.water.attenuation_per_m =
      d.log_uniform(0.1, std::max(0.12, std::min(0.7, 1.8 / camera_to_net_m)));
  s.water.backscatter = d.uniform(0.05, 0.4);
  s.water.marine_snow = d.uniform(0, 0.12);
  if (d.chance(0.3)) {  // night: the vehicle's lamps only
    s.light.ambient = d.uniform(0, 0.05);
    s.light.lamp_level = d.uniform(0.2, 1.0);
  } else {
    s.light.ambient = d.uniform(0.3, 1.5);
    s.light.lamp_level = d.uniform(0, 1);
  }
}

void draw_optics(Draw& d, CameraConfig& c) {
  c.samples_per_axis = 1;
  if (d.chance(0.4)) {  // defocus: a fixed-focus lens set for another distance
    c.focus_distance_m = d.uniform(0.5, 3);
    c.f_number = d.uniform(1.8, 4);
  }
  if (d.chance(0.3)) c.jpeg_quality = d.integer(50, 95);
}

}  // namespace

Scenario random_depth_scene(uint64_t seed) {
  Draw d(seed);
  // The parser's defaults (camera mount, intrinsics, the two lamps), then the draw.
  Scenario s = parse_scenario(
      "trajectory: {waypoints: [{t_s: 0, along_m: 0, net_distance_m: 1, depth_m: 3}]}\n",
      "depth-training.yaml");
  s.seed = d.bits();
  Waypoint w;
  const double camera_to_net_m = d.log_uniform(0.3, 5.0);
  draw_net(d, s.net, camera_to_net_m, s.camera.calibration.camera.fx_px);
  draw_water_and_light(d, s, camera_to_net_m);
  draw_optics(d, s.camera);
  w.net_distance_m = camera_to_net_m + kCameraAhead_m;
  w.heading_rad = d.uniform(-35, 35) * kDeg;
  w.pitch_rad = d.uniform(-20, 20) * kDeg;
  w.roll_rad = d.uniform(-5, 5) * kDeg;
  if (d.chance(0.15)) {  // a flat panel in a tank, with the basin wall or open water behind it
    s.pen.shape = NetShape::kPlane;
    s.pen.radius_m = 8;
    s.pen.width_m = d.uniform(3, 6);
    s.pen.top_m = d.uniform(0.2, 0.8);
    s.pen.height_m = d.uniform(1.2, 3);
    s.pen.wall_gap_m = d.chance(0.5) ? d.uniform(0.5, 2) : 0;
    w.along_m = d.uniform(-0.4, 0.4) * s.pen.width_m;
    w.depth_m = s.pen.top_m + d.uniform(0.1, 0.9) * s.pen.height_m;
    w.net_distance_m = std::min(w.net_distance_m, s.pen.radius_m - 0.5);
  } else {
    s.pen.shape = NetShape::kCylinder;
    s.pen.radius_m = d.uniform(6, 25);
    s.pen.depth_m = d.uniform(8, 20);
    w.net_distance_m = std::min(w.net_distance_m, s.pen.radius_m - 1);
    w.depth_m = d.uniform(1, s.pen.depth_m - 1);
    if (d.chance(0.1)) {  // near the bottom, looking down at where wall and bottom meet
      w.depth_m = s.pen.depth_m - d.uniform(1, 2.5);
      w.pitch_rad = d.uniform(-35, -15) * kDeg;
    } else if (d.chance(0.1)) {  // near the surface, looking up
      w.depth_m = d.uniform(0.6, 2);
      w.pitch_rad = d.uniform(15, 30) * kDeg;
    }
    if (d.chance(0.25)) {
      s.net.bulges.push_back({.along_m = w.along_m + d.uniform(-1.5, 1.5),
                              .depth_m = w.depth_m + d.uniform(-1.5, 1.5),
                              .amplitude_m = d.uniform(0.05, 0.3),
                              .radius_m = d.uniform(0.5, 2)});
    }
  }
  if (camera_to_net_m > 0.5 && d.chance(0.3)) {  // fish between the camera and the net
    const int n = d.integer(1, 3);
    for (int i = 0; i < n; ++i) {
      Fish f;
      f.net_distance_m = d.uniform(0.1, camera_to_net_m - 0.15);
      f.depth_m = w.depth_m + d.uniform(-0.4, 0.4);
      f.along_m = w.along_m + d.uniform(-0.6, 0.6);
      f.speed_mps = 0;
      f.length_m = d.uniform(0.25, 0.6);
      f.thickness_m = f.length_m * d.uniform(0.18, 0.3);
      f.albedo = d.uniform(0.2, 0.7);
      s.fish.push_back(f);
    }
  }
  s.waypoints = {w};
  s.duration_s = 0;
  validate(s);
  return s;
}

DepthSample make_depth_sample(uint64_t seed, int width, int height) {
  Scenario s = random_depth_scene(seed);
  const NetGeometry net(s.pen, s.net);
  const FrameState f = frame_state(s, 0);
  RenderedFrame r = render_cpu(s, net, f);
  // Auto-exposure as the vehicle's camera does it: one correction towards a drawn mean grey.
  const double mean = std::accumulate(r.image.pixels.begin(), r.image.pixels.end(), 0.0) /
                      static_cast<double>(r.image.pixels.size());
  const double target = Draw(seed ^ 0x5eedULL).uniform(35, 120);
  if (mean < 0.7 * target || mean > 1.4 * target) {
    s.camera.exposure *= std::clamp(target / std::max(mean, 1.0), 0.3, 30.0);
    r = render_cpu(s, net, f);
  }

  const PinholeCamera& cam = s.camera.calibration.camera;
  // What `pensight run` takes from the rendered dataset's scene.yaml.
  const SceneConfig scene = s.scene_config();
  const NetDetectorConfig config =
      detector_config(scene, {.backend = Backend::kCpu, .cpu_threads = 1});
  Device device;
  NetDetector detector(cam, config, device);
  const NetDetection detection = detector.detect(r.image);

  DepthSample out;
  out.image = resize_area(r.image, width, height);
  const ImageU16 full_mm = depth_mm_from_m(r.depth_m);
  out.depth_mm = ImageU16(width, height);
  for (int y = 0; y < height; ++y) {
    const int sy = std::min(cam.height_px - 1,
                            static_cast<int>(std::floor((y + 0.5) * cam.height_px / height)));
    for (int x = 0; x < width; ++x) {
      const int sx = std::min(cam.width_px - 1,
                              static_cast<int>(std::floor((x + 0.5) * cam.width_px / width)));
      out.depth_mm.at(x, y) = full_mm.at(sx, sy);
    }
  }
  out.points = network_depths(
      detection.depths, network_view(cam.width_px, cam.height_px, width, height), width, height);
  out.wall = {.curvature_per_m = net_curvature_per_m(scene),
              .focal_px = cam.scaled(static_cast<double>(width) / cam.width_px).fx_px};
  return out;
}

void write_depth_data(const std::filesystem::path& out, const DepthDataOptions& o) {
  namespace fs = std::filesystem;
  if (o.samples < 1 || o.width < 32 || o.height < 32) {
    throw Error("depth training data: need at least 1 sample and a size of at least 32x32");
  }
  if (fs::exists(out) && !fs::exists(out / "depth_data.txt")) {
    throw Error(out.string() +
                " exists and is not a depth training-data folder: choose another --out");
  }
  const size_t pixels = static_cast<size_t>(o.width) * o.height;
  const size_t k = kernels::kMaxSparsePoints;
  std::vector<uint8_t> images(o.samples * pixels);
  std::vector<uint16_t> depths(o.samples * pixels);
  std::vector<float> points(o.samples * k * 4, 0.0f);
  std::vector<int32_t> counts(o.samples, 0);
  std::vector<float> walls(o.samples * 2, 0.0f);

  std::atomic<int> next{0}, done{0};
  std::mutex progress_mutex;
  std::exception_ptr failure;
  auto work = [&] {
    for (int i = next++; i < o.samples && !failure; i = next++) {
      try {
        const DepthSample s = make_depth_sample(o.seed * 1'000'003ULL + i, o.width, o.height);
        std::copy(s.image.pixels.begin(), s.image.pixels.end(), images.begin() + i * pixels);
        std::copy(s.depth_mm.pixels.begin(), s.depth_mm.pixels.end(), depths.begin() + i * pixels);
        counts[i] = static_cast<int32_t>(s.points.size());
        walls[2 * i] = static_cast<float>(s.wall.curvature_per_m);
        walls[2 * i + 1] = static_cast<float>(s.wall.focal_px);
        float* p = points.data() + i * k * 4;
        for (const SparseDepth& d : s.points) {
          *p++ = d.point.x_px;
          *p++ = d.point.y_px;
          *p++ = d.point.depth_m;
          *p++ = d.quality;
        }
        const std::lock_guard lock(progress_mutex);
        if (o.progress) o.progress(++done, o.samples);
      } catch (...) {
        const std::lock_guard lock(progress_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  const int threads = worker_threads(o.threads);
  std::vector<std::jthread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(work);
  pool.clear();
  if (failure) std::rethrow_exception(failure);

  int without = 0;
  for (const int32_t c : counts) without += c == 0 ? 1 : 0;
  const fs::path staging = temporary_sibling(out);
  fs::remove_all(staging);
  fs::create_directories(staging);
  auto write = [&](const char* name, const void* data, size_t bytes) {
    std::ofstream f(staging / name, std::ios::binary);
    f.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
    if (!f.good()) {
      fs::remove_all(staging);
      throw Error("cannot write " + (staging / name).string() + ": check the disk space");
    }
  };
  write("image.u8", images.data(), images.size());
  write("depth_mm.u16", depths.data(), depths.size() * sizeof(uint16_t));
  write("points.f32", points.data(), points.size() * sizeof(float));
  write("num_points.i32", counts.data(), counts.size() * sizeof(int32_t));
  write("wall.f32", walls.data(), walls.size() * sizeof(float));
  const std::string meta =
      "version: 2\nsamples: " + std::to_string(o.samples) + "\nwidth: " + std::to_string(o.width) +
      "\nheight: " + std::to_string(o.height) + "\nmax_points: " + std::to_string(k) +
      "\nsigma_px: " + std::to_string(kernels::SparsePriorShape{}.sigma_px) +
      "\nseed: " + std::to_string(o.seed) + "\nsamples_without_priors: " + std::to_string(without) +
      "\n";
  write("depth_data.txt", meta.data(), meta.size());
  fs::remove_all(out);
  fs::rename(staging, out);
}

}  // namespace pensight::sim
