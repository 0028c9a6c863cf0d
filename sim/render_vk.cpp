#include "sim/render_vk.h"

#include <bit>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "sim/lamp_veil_table.h"
#include "sim/marine_snow.h"
#include "sim/net_geometry.h"
#include "sim/net_mesh.h"
#include "sim/optics.h"
#include "sim/sim_hash.h"
#include "sim/sim_shader.h"

namespace pensight::sim {
namespace {

using Vec4 = std::array<float, 4>;

// std430 mirror of the fixed part of FrameBuf in shaders/sim/render.comp; the spots follow.
struct FrameHeader {
  Vec4 rot[3];
  std::array<uint32_t, 4> info;
  Vec4 fish_c[kMaxFish], fish_a[kMaxFish];
};
static_assert(sizeof(FrameHeader) == 20 * 16);

// render.comp: local_size_x/y, and the rows each invocation renders (ROWS). A tile of the snow
// lists is kTile_px x kRowsPerInvocation pixels: one invocation's column of pixels.
constexpr uint32_t kGroupX = 8, kGroupY = 4, kRowsPerInvocation = 8, kTile_px = 8;
// FEATURES bits of render.comp.
constexpr uint32_t kFeatureNoise = 1, kFeatureSnow = 2, kFeaturePlane = 4, kFeatureBottom = 8,
                   kFeatureWall = 16, kFeatureFouling = 32, kFeatureDistortion = 64,
                   kFeatureRadiance = 128, kFeatureDeform = 256, kFeaturePatches = 512,
                   kFeatureRopes = 1024, kFeatureSeams = 2048, kFeatureRoundKnots = 4096;

// The shader writes the unrounded, noise-free radiance for the optics (optics.h) to work on.
bool keep_radiance(const Scenario& s, const RenderOptions& o) {
  return o.radiance_only || optics_enabled(s.camera);
}

uint32_t features(const Scenario& s, const RenderOptions& o) {
  const bool plane = s.pen.shape == NetShape::kPlane;
  uint32_t f = 0;
  if (keep_radiance(s, o)) {
    f |= kFeatureRadiance;
  } else if (o.noise && (s.camera.read_noise > 0 || s.camera.shot_noise > 0)) {
    f |= kFeatureNoise;
  }
  if (o.marine_snow && s.water.marine_snow > 0) f |= kFeatureSnow;
  if (plane) f |= kFeaturePlane;
  if (!plane && s.pen.bottom) f |= kFeatureBottom;
  if (plane && s.pen.wall_gap_m > 0) f |= kFeatureWall;
  if (s.net.fouling > 0) f |= kFeatureFouling;
  if (s.camera.calibration.camera.has_distortion()) f |= kFeatureDistortion;
  if (s.net.opening_angle_variation_deg > 0 || s.net.stretch_variation > 0) f |= kFeatureDeform;
  if (s.net.fouling_coverage > 0) f |= kFeaturePatches;
  if (s.net.ropes.spacing_m > 0) f |= kFeatureRopes;
  if (s.net.seam_spacing_m > 0) f |= kFeatureSeams;
  if (s.net.knot_shape == KnotShape::kRound) f |= kFeatureRoundKnots;
  return f;
}

uint32_t bits(double v) {
  return std::bit_cast<uint32_t>(static_cast<float>(v));
}

Vec4 v4(double a, double b, double c, double d) {
  return {static_cast<float>(a), static_cast<float>(b), static_cast<float>(c),
          static_cast<float>(d)};
}

// The lamps in the camera frame (fixed to the body, like the camera).
std::vector<LampPose> lamps_in_camera(const Scenario& s) {
  const Eigen::Isometry3d T_camera_body = s.camera.calibration.T_body_camera.inverse();
  std::vector<LampPose> out;
  for (const Lamp& l : s.light.lamps) {
    LampPose p;
    p.position_m = T_camera_body * l.position_B_m;
    p.direction = T_camera_body.linear() * l.direction_B;
    p.intensity = l.intensity * s.light.lamp_level;
    p.exponent = std::log(0.5) / std::log(std::cos(l.half_angle_rad));
    out.push_back(p);
  }
  return out;
}

// The specialization constants of render.comp, in constant_id order.
std::vector<uint32_t> specialization(const Scenario& s, const RenderOptions& o) {
  const PinholeCamera& k = s.camera.calibration.camera;
  const NetGeometry geometry(s.pen, s.net);
  const NetLattice lattice(s.net, geometry.u_around(), s.seed);
  const PenConfig& pen = s.pen;
  const NetConfig& net = s.net;
  const WaterConfig& w = s.water;
  const CameraConfig& c = s.camera;
  const int cells = geometry.fouling_cells_around();
  std::vector<uint32_t> v = {static_cast<uint32_t>(k.width_px),
                             static_cast<uint32_t>(k.height_px),
                             static_cast<uint32_t>(c.samples_per_axis),
                             static_cast<uint32_t>(net.bulges.size()),
                             static_cast<uint32_t>(s.light.lamps.size()),
                             static_cast<uint32_t>(s.fish.size()),
                             features(s, o),
                             bits(k.fx_px),
                             bits(k.fy_px),
                             bits(k.cx_px),
                             bits(k.cy_px),
                             bits(k.k1),
                             bits(k.k2),
                             bits(k.p1),
                             bits(k.p2),
                             bits(pen.radius_m),
                             bits(pen.depth_m),
                             bits(pen.width_m),
                             bits(pen.top_m),
                             bits(pen.height_m),
                             bits(pen.wall_gap_m),
                             bits(net.bar_length_m),
                             bits(net.twine_width_m),
                             bits(net.knot_size_m),
                             bits(net.albedo),
                             bits(net.fouling),
                             bits(geometry.fouling_cell_u()),
                             bits(net.fouling_scale_m),
                             bits(lattice.normal_a().x()),
                             bits(lattice.normal_a().y()),
                             bits(geometry.lattice_scale()),
                             static_cast<uint32_t>(cells),
                             bits(w.attenuation_per_m),
                             bits(w.diffuse_attenuation_per_m),
                             bits(w.lamp_backscatter),
                             bits(s.light.ambient),
                             bits(s.light.surface_brightness),
                             bits(pen.wall_albedo),
                             bits(255.0 * c.exposure),
                             bits(c.vignetting),
                             bits(c.read_noise),
                             bits(c.shot_noise),
                             fold_seed(s.seed),
                             bits(net_visible_range_m(w))};
  for (size_t i = 0; i < kMaxBulges; ++i) {
    const Bulge b = i < net.bulges.size() ? net.bulges[i] : Bulge{};
    // A fold's half width is sent negative (render.comp's displacement()).
    for (double x : {b.along_m, b.depth_m, b.amplitude_m, b.fold ? -b.radius_m : b.radius_m}) {
      v.push_back(bits(x));
    }
  }
  const std::vector<LampPose> lamps = lamps_in_camera(s);
  for (size_t i = 0; i < kMaxLamps; ++i) {
    LampPose l;
    l.position_m.setZero();
    l.direction = Eigen::Vector3d::UnitZ();
    if (i < lamps.size()) l = lamps[i];
    for (int j = 0; j < 3; ++j) v.push_back(bits(l.position_m[j]));
    for (int j = 0; j < 3; ++j) v.push_back(bits(l.direction[j]));
    v.push_back(bits(l.intensity));
    v.push_back(bits(l.exponent));
  }
  for (size_t i = 0; i < kMaxFish; ++i) {
    const Fish f = i < s.fish.size() ? s.fish[i] : Fish{};
    for (double x : {f.length_m / 2, f.thickness_m / 2, f.albedo}) v.push_back(bits(x));
  }
  const auto& ph = lattice.phases();
  for (double x : {lattice.normal_b().x(),
                   lattice.normal_b().y(),
                   lattice.period(),
                   lattice.normals_dot(),
                   lattice.round_knot_mean(),
                   lattice.bisector().x(),
                   lattice.bisector().y(),
                   lattice.k_stretch(),
                   lattice.k_angle(),
                   lattice.amp_stretch(),
                   lattice.amp_angle(),
                   ph[0],
                   ph[1],
                   ph[2],
                   ph[3],
                   lattice.fade_m(),
                   lattice.u_around(),
                   lattice.patch_threshold(),
                   lattice.clump_cells_u().period,
                   lattice.clump_cell_v()}) {
    v.push_back(bits(x));
  }
  v.push_back(static_cast<uint32_t>(lattice.clump_cells_u().count));
  for (double x : {lattice.clump_mean(), lattice.rope_u().period, net.ropes.spacing_m,
                   net.ropes.width_m, net.ropes.albedo, lattice.seam_u().period, net.seam_spacing_m,
                   kSeamTwines * net.twine_width_m}) {
    v.push_back(bits(x));
  }
  v.push_back(LampVeilTable::kStep_px);
  v.push_back(LampVeilTable::kNodes);
  // The last constant_id of render.comp is 162.
  if (v.size() != 163)
    throw Error("render_vk: specialization constants out of step with render.comp");
  return v;
}

// The veil table of render.comp's VeilBuf; one unused cell without lamps or backscatter.
std::shared_ptr<const vk::Buffer> veil_buffer(const vk::Context& ctx, const Scenario& s) {
  std::vector<std::array<float, 4>> cells(1, {0, 0, 0, 0});
  if (!s.light.lamps.empty() && s.water.lamp_backscatter > 0) {
    cells =
        LampVeilTable(s.camera.calibration.camera, lamps_in_camera(s), s.water.attenuation_per_m,
                      s.water.lamp_backscatter, net_visible_range_m(s.water))
            .cells();
  }
  auto buffer = std::make_shared<vk::Buffer>(ctx, cells.size() * sizeof(cells[0]));
  buffer->upload(cells.data(), cells.size() * sizeof(cells[0]));
  return buffer;
}

uint32_t tile_columns(int width) {
  return (static_cast<uint32_t>(width) + kTile_px - 1) / kTile_px;
}

// Spot indices per tile, for the shader's tile lists: offsets (tiles + 1, absolute positions in
// the returned array), then the indices.
std::vector<uint32_t> bin_spots(const std::vector<SnowSpot>& spots, int width, int height) {
  const uint32_t cols = tile_columns(width);
  const uint32_t rows =
      (static_cast<uint32_t>(height) + kRowsPerInvocation - 1) / kRowsPerInvocation;
  const size_t tiles = static_cast<size_t>(cols) * rows;
  struct Range {
    uint32_t x0, x1, y0, y1;
  };
  std::vector<Range> ranges;
  std::vector<uint32_t> count(tiles, 0);
  for (const SnowSpot& s : spots) {
    const double reach = kSnowCutoffSigmas * s.sigma_px;
    auto tile_of = [](double px, double lo, double hi, uint32_t size) {
      return static_cast<uint32_t>(std::clamp(px, lo, hi)) / size;
    };
    const Range r{tile_of(std::ceil(s.x_px - reach), 0, width - 1, kTile_px),
                  tile_of(std::floor(s.x_px + reach), 0, width - 1, kTile_px),
                  tile_of(std::ceil(s.y_px - reach), 0, height - 1, kRowsPerInvocation),
                  tile_of(std::floor(s.y_px + reach), 0, height - 1, kRowsPerInvocation)};
    for (uint32_t ty = r.y0; ty <= r.y1; ++ty) {
      for (uint32_t tx = r.x0; tx <= r.x1; ++tx) ++count[ty * cols + tx];
    }
    ranges.push_back(r);
  }
  std::vector<uint32_t> out(tiles + 1);
  out[0] = static_cast<uint32_t>(tiles + 1);
  for (size_t t = 0; t < tiles; ++t) out[t + 1] = out[t] + count[t];
  out.resize(out[tiles]);
  std::vector<uint32_t> next(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(tiles));
  for (uint32_t i = 0; i < ranges.size(); ++i) {
    const Range& r = ranges[i];
    for (uint32_t ty = r.y0; ty <= r.y1; ++ty) {
      for (uint32_t tx = r.x0; tx <= r.x1; ++tx) out[next[ty * cols + tx]++] = i;
    }
  }
  return out;
}

}  // namespace

struct RenderVk::Resources {
  vk::Buffer frame, tiles;
  vk::TypedBuffer<float> image, depth;
  vk::CommandStream stream;
  Resources(const vk::Context& ctx, size_t frame_bytes, size_t tile_bytes, size_t pixels)
      : frame(ctx, frame_bytes),
        tiles(ctx, tile_bytes),
        image(ctx, pixels),
        depth(ctx, pixels),
        stream(ctx) {}
};

RenderVk::RenderVk(const vk::Context& ctx, const Scenario& s, const RenderOptions& options)
    : ctx_(&ctx),
      s_(s),
      options_(options),
      pipeline_(&ctx.pipeline({.shader = sim_shader("sim/render"),
                               .num_buffers = 5,
                               .push_constant_bytes = 0,
                               .specialization = specialization(s, options)})),
      veil_(veil_buffer(ctx, s)) {}

int RenderVk::width() const {
  return s_.camera.calibration.camera.width_px;
}
int RenderVk::height() const {
  return s_.camera.calibration.camera.height_px;
}

RenderVk::FrameData RenderVk::frame_data(const FrameState& f) const {
  if (f.lamps.size() != s_.light.lamps.size() || f.fish.size() != s_.fish.size()) {
    throw Error("RenderVk: the frame does not belong to the scenario the renderer was built for");
  }
  // The shader holds the lamps in the camera frame as constants: they must ride with the body.
  const std::vector<LampPose> lamps = lamps_in_camera(s_);
  for (size_t i = 0; i < lamps.size(); ++i) {
    if ((f.T_pen_camera * lamps[i].position_m - f.lamps[i].position_m).norm() > 1e-6 ||
        (f.T_pen_camera.linear() * lamps[i].direction - f.lamps[i].direction).norm() > 1e-6) {
      throw Error("RenderVk: lamp " + std::to_string(i) +
                  " is not fixed to the vehicle as the scenario describes it");
    }
  }
  FrameHeader h{};
  const Eigen::Matrix3d R = f.T_pen_camera.linear();
  const Eigen::Vector3d o = f.T_pen_camera.translation();
  for (int r = 0; r < 3; ++r) h.rot[r] = v4(R(r, 0), R(r, 1), R(r, 2), o[r]);
  const WaterConfig& w = s_.water;
  const double background = w.backscatter * s_.light.ambient *
                            std::exp(-w.diffuse_attenuation_per_m * std::max(o.z(), 0.0));
  h.info = {static_cast<uint32_t>(f.frame), bits(background), tile_columns(width()), 0};
  for (size_t i = 0; i < f.fish.size(); ++i) {
    h.fish_c[i] = v4(f.fish[i].centre_m.x(), f.fish[i].centre_m.y(), f.fish[i].centre_m.z(), 0);
    h.fish_a[i] = v4(f.fish[i].axis.x(), f.fish[i].axis.y(), f.fish[i].axis.z(), 0);
  }
  std::vector<SnowSpot> spots;
  if (options_.marine_snow) spots = snow_spots(s_, f);
  FrameData d;
  d.frame.resize(sizeof h + spots.size() * sizeof(Vec4));
  std::memcpy(d.frame.data(), &h, sizeof h);
  for (size_t i = 0; i < spots.size(); ++i) {
    const SnowSpot& s = spots[i];
    const Vec4 v = v4(s.x_px, s.y_px, 1 / (s.sigma_px * s.sigma_px), s.peak);
    std::memcpy(d.frame.data() + sizeof h + i * sizeof v, &v, sizeof v);
  }
  d.tiles = bin_spots(spots, width(), height());
  return d;
}

void RenderVk::record(vk::CommandStream& stream, const vk::Buffer& frame, const vk::Buffer& tiles,
                      const vk::Buffer& image, const vk::Buffer& depth) const {
  const size_t pixels = static_cast<size_t>(width()) * height();
  const size_t tile_offsets =
      static_cast<size_t>(tile_columns(width())) *
          ((static_cast<size_t>(height()) + kRowsPerInvocation - 1) / kRowsPerInvocation) +
      1;
  if (frame.size_bytes() < sizeof(FrameHeader) || tiles.size_bytes() < tile_offsets * 4 ||
      image.size_bytes() < pixels * sizeof(float) || depth.size_bytes() < pixels * sizeof(float)) {
    throw Error(
        "RenderVk::record: a buffer is smaller than the image size needs (frame_data() "
        "gives the frame and tile sizes)");
  }
  const uint32_t columns = static_cast<uint32_t>(width());
  const uint32_t rows =
      (static_cast<uint32_t>(height()) + kRowsPerInvocation - 1) / kRowsPerInvocation;
  stream.dispatch(*pipeline_,
                  {vk::in(frame), vk::in(tiles), vk::out(image), vk::out(depth), vk::in(*veil_)},
                  {(columns + kGroupX - 1) / kGroupX, (rows + kGroupY - 1) / kGroupY, 1}, nullptr,
                  0, "sim_render");
}

RenderedFrame RenderVk::render(const FrameState& f) {
  const size_t pixels = static_cast<size_t>(width()) * height();
  const FrameData d = frame_data(f);
  const size_t tile_bytes = d.tiles.size() * sizeof(uint32_t);
  if (!res_ || res_->frame.size_bytes() < d.frame.size() || res_->tiles.size_bytes() < tile_bytes) {
    // Room for twice this frame's snow, so the buffers rarely grow again.
    res_ = std::make_shared<Resources>(*ctx_, 2 * d.frame.size(), 2 * tile_bytes, pixels);
    record(res_->stream, res_->frame, res_->tiles, res_->image.raw(), res_->depth.raw());
  }
  res_->frame.upload(d.frame.data(), d.frame.size());
  res_->tiles.upload(d.tiles.data(), tile_bytes);
  res_->stream.submit_and_wait();
  RenderedFrame out;
  out.depth_m = ImageF32(width(), height());
  res_->depth.download(out.depth_m.pixels);
  if (keep_radiance(s_, options_)) {
    out.radiance = ImageF32(width(), height());
    res_->image.download(out.radiance.pixels);
    if (!options_.radiance_only) apply_optics(s_, f, options_, out);
    return out;
  }
  out.image = ImageU8(width(), height());
  const std::vector<float> grey = res_->image.to_vector();
  for (size_t i = 0; i < pixels; ++i) out.image.pixels[i] = static_cast<uint8_t>(grey[i]);
  return out;
}

}  // namespace pensight::sim
