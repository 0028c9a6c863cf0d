#include "sim/render_vk.h"

#include <bit>
#include <cmath>
#include <cstring>

#include "runtime/error.h"
#include "sim/sim_hash.h"

namespace pensight::sim {
namespace {

using Vec4 = std::array<float, 4>;
using UVec4 = std::array<uint32_t, 4>;

// std430 mirror of `Params` in shaders/sim/render.comp (every member 16-byte aligned).
struct GpuParams {
  Vec4 cam, dist, rot[3], origin, pen, plane, net, net2, water, light, camera;
  UVec4 counts;
  Vec4 bulge[kMaxBulges], lamp_pos[kMaxLamps], lamp_dir[kMaxLamps];
  Vec4 fish_c[kMaxFish], fish_a[kMaxFish], fish_t[kMaxFish];
};
static_assert(sizeof(GpuParams) == 54 * 16);

constexpr uint32_t kWorkgroup = 8;  // local_size_x/y in render.comp
// FEATURES bits of render.comp.
constexpr uint32_t kFeatureNoise = 1, kFeatureSnow = 2, kFeaturePlane = 4, kFeatureBottom = 8,
                   kFeatureWall = 16, kFeatureFouling = 32, kFeatureDistortion = 64;

uint32_t features(const Scenario& s, const RenderOptions& o) {
  const bool plane = s.pen.shape == NetShape::kPlane;
  uint32_t f = 0;
  if (o.noise && (s.camera.read_noise > 0 || s.camera.shot_noise > 0)) f |= kFeatureNoise;
  if (o.marine_snow && s.water.marine_snow > 0) f |= kFeatureSnow;
  if (plane) f |= kFeaturePlane;
  if (!plane && s.pen.bottom) f |= kFeatureBottom;
  if (plane && s.pen.wall_gap_m > 0) f |= kFeatureWall;
  if (s.net.fouling > 0) f |= kFeatureFouling;
  if (s.camera.calibration.camera.has_distortion()) f |= kFeatureDistortion;
  return f;
}

Vec4 v4(double a, double b, double c, double d) {
  return {static_cast<float>(a), static_cast<float>(b), static_cast<float>(c),
          static_cast<float>(d)};
}
Vec4 v4(const Eigen::Vector3d& v, double w) {
  return v4(v.x(), v.y(), v.z(), w);
}

}  // namespace

struct RenderVk::Resources {
  vk::Buffer params;
  vk::TypedBuffer<float> image, depth;
  vk::CommandStream stream;
  Resources(const vk::Context& ctx, size_t pixels)
      : params(ctx, sizeof(GpuParams)), image(ctx, pixels), depth(ctx, pixels), stream(ctx) {}
};

RenderVk::RenderVk(const vk::Context& ctx, const Scenario& s, const RenderOptions& options)
    : ctx_(&ctx),
      s_(s),
      options_(options),
      pipeline_(ctx,
                {.shader = "sim/render",
                 .num_buffers = 3,
                 .push_constant_bytes = 0,
                 .specialization = {static_cast<uint32_t>(s.camera.calibration.camera.width_px),
                                    static_cast<uint32_t>(s.camera.calibration.camera.height_px),
                                    static_cast<uint32_t>(s.camera.samples_per_axis),
                                    static_cast<uint32_t>(s.net.bulges.size()),
                                    static_cast<uint32_t>(s.light.lamps.size()),
                                    static_cast<uint32_t>(s.fish.size()), features(s, options)}}) {}

int RenderVk::width() const {
  return s_.camera.calibration.camera.width_px;
}
int RenderVk::height() const {
  return s_.camera.calibration.camera.height_px;
}

size_t RenderVk::params_bytes() {
  return sizeof(GpuParams);
}

std::vector<uint8_t> RenderVk::params(const FrameState& f) const {
  GpuParams g{};
  const PinholeCamera& k = s_.camera.calibration.camera;
  g.cam = v4(k.fx_px, k.fy_px, k.cx_px, k.cy_px);
  g.dist = v4(k.k1, k.k2, k.p1, k.p2);
  const Eigen::Matrix3d R = f.T_world_camera.linear();
  for (int r = 0; r < 3; ++r) g.rot[r] = v4(R(r, 0), R(r, 1), R(r, 2), 0);
  const Eigen::Vector3d o = f.T_world_camera.translation();
  g.origin = v4(o, net_visible_range_m(s_.water));
  const PenConfig& pen = s_.pen;
  g.pen = v4(pen.radius_m, pen.depth_m, pen.bottom ? 1 : 0, pen.shape == NetShape::kPlane ? 1 : 0);
  g.plane = v4(pen.width_m, pen.top_m, pen.height_m, pen.wall_gap_m);
  const NetConfig& net = s_.net;
  g.net = v4(net.mesh_m, net.twine_width_m, net.knot_size_m, net.albedo);
  g.net2 = v4(net.fouling, net.fouling_scale_m, std::cos(net.mesh_angle_rad),
              std::sin(net.mesh_angle_rad));
  const WaterConfig& w = s_.water;
  const double ambient_at_camera =
      s_.light.ambient * std::exp(-w.diffuse_attenuation_per_m * std::max(o.z(), 0.0));
  g.water = v4(w.attenuation_per_m, w.diffuse_attenuation_per_m, w.backscatter * ambient_at_camera,
               w.lamp_backscatter);
  double snow_light = 0.5 * ambient_at_camera;
  for (const LampPose& l : f.lamps) snow_light += l.intensity;
  g.light = v4(s_.light.ambient, s_.light.surface_brightness, pen.wall_albedo,
               w.snow_brightness * snow_light);
  const CameraConfig& c = s_.camera;
  g.camera = v4(255.0 * c.exposure, c.vignetting, c.read_noise, c.shot_noise);
  g.counts = {static_cast<uint32_t>(f.frame), fold_seed(s_.seed),
              std::bit_cast<uint32_t>(static_cast<float>(w.marine_snow)), 0};
  if (f.lamps.size() != s_.light.lamps.size() || f.fish.size() != s_.fish.size()) {
    throw Error("RenderVk::params: the frame does not belong to the scenario it was built for");
  }
  for (size_t i = 0; i < net.bulges.size(); ++i) {
    const Bulge& b = net.bulges[i];
    g.bulge[i] = v4(b.along_m, b.depth_m, b.amplitude_m, b.radius_m);
  }
  for (size_t i = 0; i < f.lamps.size(); ++i) {
    g.lamp_pos[i] = v4(f.lamps[i].position_m, f.lamps[i].intensity);
    g.lamp_dir[i] = v4(f.lamps[i].direction, f.lamps[i].exponent);
  }
  for (size_t i = 0; i < f.fish.size(); ++i) {
    g.fish_c[i] = v4(f.fish[i].centre_m, f.fish[i].albedo);
    g.fish_a[i] = v4(f.fish[i].axis, f.fish[i].half_length_m);
    g.fish_t[i] = v4(f.fish[i].half_thickness_m, 0, 0, 0);
  }
  std::vector<uint8_t> bytes(sizeof g);
  std::memcpy(bytes.data(), &g, sizeof g);
  return bytes;
}

void RenderVk::record(vk::CommandStream& stream, const vk::Buffer& params, const vk::Buffer& image,
                      const vk::Buffer& depth) const {
  const size_t pixels = static_cast<size_t>(width()) * height();
  if (params.size_bytes() < sizeof(GpuParams) || image.size_bytes() < pixels * sizeof(float) ||
      depth.size_bytes() < pixels * sizeof(float)) {
    throw Error("RenderVk::record: a buffer is smaller than the image size needs");
  }
  stream.dispatch(pipeline_, {vk::in(params), vk::out(image), vk::out(depth)},
                  {(static_cast<uint32_t>(width()) + kWorkgroup - 1) / kWorkgroup,
                   (static_cast<uint32_t>(height()) + kWorkgroup - 1) / kWorkgroup, 1},
                  nullptr, 0, "sim_render");
}

RenderedFrame RenderVk::render(const FrameState& f) {
  const size_t pixels = static_cast<size_t>(width()) * height();
  if (!res_) {
    res_ = std::make_shared<Resources>(*ctx_, pixels);
    record(res_->stream, res_->params, res_->image.raw(), res_->depth.raw());
  }
  const auto bytes = params(f);
  res_->params.upload(bytes.data(), bytes.size());
  res_->stream.submit_and_wait();
  RenderedFrame out{ImageU8(width(), height()), ImageF32(width(), height())};
  const std::vector<float> grey = res_->image.to_vector();
  for (size_t i = 0; i < pixels; ++i) out.image.pixels[i] = static_cast<uint8_t>(grey[i]);
  res_->depth.download(out.depth_m.pixels);
  return out;
}

}  // namespace pensight::sim
