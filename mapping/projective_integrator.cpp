#include "mapping/projective_integrator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "runtime/simd_clones.h"

namespace pensight::mapping {
namespace {

using Leaf = openvdb::FloatTree::LeafNodeType;
using MaskTree = openvdb::MaskTree;
constexpr int kLeafDim = static_cast<int>(Leaf::DIM);  // 8
constexpr int kTopBlock = 8 * kLeafDim;                // 64 voxels per side

// The frame's projection: P -> C and the pixel footprint of an axis-aligned box of P.
struct Projection {
  Eigen::Matrix3d R_camera_pen;
  Eigen::Vector3d t_camera_pen;
  Eigen::Vector3d box_extent;  // |R_camera_pen| * (1, 1, 1): C half-extent of a unit half-cube
  double fx, fy, cx, cy;
  int width, height;

  // A box of P (centre, half-size h) seen in C: its centre and half-extents.
  struct Footprint {
    double z_near, z_far;
    double u_min, u_max, v_min, v_max;  // pixel coordinates; valid only when z_near > 0
  };
  Footprint footprint(const Eigen::Vector3d& centre_C, double h) const {
    const Eigen::Vector3d e = box_extent * h;
    Footprint f;
    f.z_near = centre_C.z() - e.z();
    f.z_far = centre_C.z() + e.z();
    if (f.z_near <= 0) return f;
    // The box's lateral extent over its depth range: its smallest and largest x/z and y/z.
    const double x0 = centre_C.x() - e.x(), x1 = centre_C.x() + e.x();
    const double y0 = centre_C.y() - e.y(), y1 = centre_C.y() + e.y();
    f.u_min = fx * (x0 >= 0 ? x0 / f.z_far : x0 / f.z_near) + cx;
    f.u_max = fx * (x1 >= 0 ? x1 / f.z_near : x1 / f.z_far) + cx;
    f.v_min = fy * (y0 >= 0 ? y0 / f.z_far : y0 / f.z_near) + cy;
    f.v_max = fy * (y1 >= 0 ? y1 / f.z_near : y1 / f.z_far) + cy;
    return f;
  }
  bool inside_image(const Footprint& f) const {
    return f.u_min >= -0.5 && f.v_min >= -0.5 && f.u_max < width - 0.5 && f.v_max < height - 0.5;
  }
  bool misses_image(const Footprint& f) const {
    return f.u_max < -0.5 || f.v_max < -0.5 || f.u_min >= width - 0.5 || f.v_min >= height - 0.5;
  }
};

// floor(x) as an int for |x| < 2^31, without a call: the build targets baseline x86-64, which
// has no rounding instruction, so std::floor is a library call (the hit pass does three per
// pixel).
int floor_to_int(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i);
}

int pixel_of(double u) {
  return floor_to_int(u + 0.5);
}

// Index coordinates are offset by kIndexOffset before truncation, so truncation is floor for
// maps within 2^20 voxels (20 km at 2 cm) of the origin and the row loop has no branch.
constexpr double kIndexOffset = 1 << 20;
constexpr int kNoVoxel = std::numeric_limits<int>::min();

// The voxel holding each pixel's back-projected point along one image row, or kNoVoxel (x
// only) where the pixel has no depth in [min_range, max_range]: p = d * (ray0 + x * ray_step) + t
// in index units, ray0 and ray_step the row's first ray and its step along x in index space.
// Written so the compiler vectorises it (AVX2 in the x86-64-v3 clone).
PENSIGHT_SIMD_CLONES void row_voxels(const float* __restrict depth, int width, const double* ray0,
                                     const double* ray_step, const double* t, float min_range,
                                     float max_range, int* __restrict ix, int* __restrict iy,
                                     int* __restrict iz) {
  const double r0x = ray0[0], r0y = ray0[1], r0z = ray0[2];
  const double sx = ray_step[0], sy = ray_step[1], sz = ray_step[2];
  const double tx = t[0] + 0.5 + kIndexOffset, ty = t[1] + 0.5 + kIndexOffset,
               tz = t[2] + 0.5 + kIndexOffset;
  const int offset = 1 << 20;
  for (int x = 0; x < width; ++x) {
    const float d = depth[x];
    const bool valid = d >= min_range && d <= max_range;  // false for NaN
    const double dd = valid ? static_cast<double>(d) : 0.0;
    const double xd = static_cast<double>(x);
    const int cx = static_cast<int>(dd * (r0x + xd * sx) + tx) - offset;
    iy[x] = static_cast<int>(dd * (r0y + xd * sy) + ty) - offset;
    iz[x] = static_cast<int>(dd * (r0z + xd * sz) + tz) - offset;
    ix[x] = valid ? cx : kNoVoxel;
  }
}

// kEdge: crosses the image border. kFarEdge: the same beyond kFineEdgeRange_m; a leaf there
// holding no hit is decided in sub-blocks of 2^3 and more only: its voxels cut by the border stay
// unknown (the camera sweeps them into view in later frames), which spares the per-voxel tests of
// the frustum's far side surface, most of a distant view's leaves. Near the camera, where the
// border leaves cover much of the view and the water matters to the vehicle, every voxel is
// tested.
enum class BlockKind { kSkip, kFree, kSurface, kEdge, kFarEdge };
constexpr double kFineEdgeRange_m = 2.5;
enum class Decision : char { kUndecided, kFree, kNotFree };

struct Classifier {
  const Projection& proj;
  const DepthPyramid& pyramid;
  double voxel_m, max_range_m, free_margin_m;

  // Block of `size` voxels per side from index `origin`.
  BlockKind classify(const openvdb::Coord& origin, int size) const {
    const Eigen::Vector3d centre_pen = (Eigen::Vector3d(origin.x(), origin.y(), origin.z()) +
                                        Eigen::Vector3d::Constant(0.5 * (size - 1))) *
                                       voxel_m;
    const Eigen::Vector3d c = proj.R_camera_pen * centre_pen + proj.t_camera_pen;
    const Projection::Footprint f = proj.footprint(c, 0.5 * size * voxel_m);
    if (f.z_far <= 0 || f.z_near > max_range_m) return BlockKind::kSkip;
    if (f.z_near <= 0) return BlockKind::kSurface;  // straddles the camera plane: look closer
    if (proj.misses_image(f)) return BlockKind::kSkip;
    const DepthPyramid::Bounds b =
        pyramid.query(pixel_of(f.u_min), pixel_of(f.v_min), pixel_of(f.u_max), pixel_of(f.v_max));
    if (f.z_near > b.far_m) return BlockKind::kSkip;  // hidden or unknown
    if (!proj.inside_image(f)) {
      return f.z_near > kFineEdgeRange_m ? BlockKind::kFarEdge : BlockKind::kEdge;
    }
    if (f.z_far < b.near_m - free_margin_m && f.z_far <= max_range_m) return BlockKind::kFree;
    return BlockKind::kSurface;
  }
};

struct LeafTask {
  openvdb::Coord origin;
  bool free;  // cleared as a whole
  Leaf* leaf = nullptr;
  bool coarse = false;  // decided in sub-blocks only (BlockKind::kFarEdge without hits)
};

}  // namespace

ProjectiveIntegrator::ProjectiveIntegrator(const PinholeCamera& camera, const MapConfig& config)
    : camera_(camera),
      config_(config),
      arena_(config.threads > 0 ? config.threads : tbb::task_arena::automatic) {
  validate(config_);
  if (camera_.has_distortion()) {
    throw Error(
        "projective integrator: the depth camera has lens distortion; give it an undistorted "
        "(pinhole) depth image and camera");
  }
}

IntegrationStats ProjectiveIntegrator::integrate(OccupancyMap& map, const ImageF32& depth_m,
                                                 const Eigen::Isometry3d& T_pen_camera) {
  IntegrationStats stats;
  arena_.execute([&] { stats = integrate_in_arena(map, depth_m, T_pen_camera); });
  return stats;
}

IntegrationStats ProjectiveIntegrator::integrate_in_arena(OccupancyMap& map,
                                                          const ImageF32& depth_m,
                                                          const Eigen::Isometry3d& T_pen_camera) {
  IntegrationStats stats;
  check_image_size(depth_m.width, depth_m.height, camera_, "projective integrator", "depth image");
  if (map.config().voxel_m != config_.voxel_m) {
    throw Error("projective integrator: the map's voxel is " +
                std::to_string(map.config().voxel_m) + " m, the integrator's " +
                std::to_string(config_.voxel_m) + " m");
  }
  if (!T_pen_camera.matrix().allFinite()) return stats;
  stats.integrated = true;

  const double v = config_.voxel_m;
  const auto max_range = static_cast<float>(config_.max_range_m);
  pyramid_.build(depth_m, static_cast<float>(config_.min_range_m), max_range);

  Projection proj;
  proj.R_camera_pen = T_pen_camera.rotation().transpose();
  proj.t_camera_pen = -proj.R_camera_pen * T_pen_camera.translation();
  proj.box_extent = proj.R_camera_pen.cwiseAbs() * Eigen::Vector3d::Ones();
  proj.fx = camera_.fx_px;
  proj.fy = camera_.fy_px;
  proj.cx = camera_.cx_px;
  proj.cy = camera_.cy_px;
  proj.width = camera_.width_px;
  proj.height = camera_.height_px;

  // Hits: one mask per worker, joined.
  const Eigen::Matrix3d R_index_camera = T_pen_camera.rotation() / v;
  const Eigen::Vector3d t_index = T_pen_camera.translation() / v;
  const float min_range = static_cast<float>(config_.min_range_m);
  const int W = depth_m.width;
  // Index-space ray of pixel (x, y): R_index_camera * ((x - cx) / fx, (y - cy) / fy, 1).
  const Eigen::Vector3d ray_step = R_index_camera.col(0) / camera_.fx_px;
  struct HitBody {
    const ImageF32* depth;
    const PinholeCamera* cam;
    const Eigen::Matrix3d* R;
    const Eigen::Vector3d* t;
    const Eigen::Vector3d* ray_step;
    float min_range, max_range;
    MaskTree mask;
    HitBody(const HitBody& o, tbb::split)
        : depth(o.depth),
          cam(o.cam),
          R(o.R),
          t(o.t),
          ray_step(o.ray_step),
          min_range(o.min_range),
          max_range(o.max_range) {}
    HitBody(const ImageF32* d, const PinholeCamera* c, const Eigen::Matrix3d* r,
            const Eigen::Vector3d* tt, const Eigen::Vector3d* step, float lo, float hi)
        : depth(d), cam(c), R(r), t(tt), ray_step(step), min_range(lo), max_range(hi) {}
    void operator()(const tbb::blocked_range<int>& rows) {
      openvdb::tree::ValueAccessor<MaskTree> acc(mask);
      const auto w = static_cast<size_t>(depth->width);
      std::vector<int> ix(w), iy(w), iz(w);
      openvdb::Coord last(std::numeric_limits<int>::max());
      for (int y = rows.begin(); y < rows.end(); ++y) {
        const Eigen::Vector3d ray0 =
            *R * Eigen::Vector3d(-cam->cx_px / cam->fx_px, (y - cam->cy_px) / cam->fy_px, 1.0);
        row_voxels(&depth->at(0, y), depth->width, ray0.data(), ray_step->data(), t->data(),
                   min_range, max_range, ix.data(), iy.data(), iz.data());
        for (size_t x = 0; x < w; ++x) {
          if (ix[x] == kNoVoxel) continue;
          const openvdb::Coord c(ix[x], iy[x], iz[x]);
          if (c == last) continue;  // neighbouring pixels mostly share a voxel
          last = c;
          acc.setValueOn(c);
        }
      }
    }
    void join(HitBody& other) { mask.topologyUnion(other.mask); }
  };
  HitBody hits(&depth_m, &camera_, &R_index_camera, &t_index, &ray_step, min_range, max_range);
  tbb::parallel_reduce(tbb::blocked_range<int>(0, depth_m.height, 16), hits);
  stats.hit_voxels = hits.mask.activeVoxelCount();

  // Blocks: the frustum's bounding box up to the farthest depth, coarse to fine.
  const Classifier classifier{proj, pyramid_, v, config_.max_range_m, config_.free_margin_m};
  const DepthPyramid::Bounds all = pyramid_.query(0, 0, W - 1, depth_m.height - 1);
  const double far_m = std::min<double>(all.far_m, config_.max_range_m) + v;
  Eigen::AlignedBox3d frustum(T_pen_camera.translation());
  for (const double u : {-0.5, W - 0.5}) {
    for (const double vv : {-0.5, depth_m.height - 0.5}) {
      const Eigen::Vector3d ray((u - proj.cx) / proj.fx, (vv - proj.cy) / proj.fy, 1.0);
      frustum.extend(T_pen_camera * (ray * far_m));
    }
  }
  auto block_floor = [](double x) {
    return static_cast<int>(std::floor(x / kTopBlock)) * kTopBlock;
  };
  std::vector<LeafTask> tasks;
  auto acc = map.grid().getAccessor();
  const auto min_lo = static_cast<float>(config_.min_log_odds);
  const auto miss = static_cast<float>(config_.miss_log_odds);
  // A free leaf that is a tile (unknown, or free from earlier frames) stays one: its one value
  // takes the miss, so open water is never allocated voxel by voxel. Stored leaves are updated
  // in the parallel pass below.
  auto add_free = [&](const openvdb::Coord& origin, int size) {
    for (int x = 0; x < size; x += kLeafDim) {
      for (int y = 0; y < size; y += kLeafDim) {
        for (int z = 0; z < size; z += kLeafDim) {
          const openvdb::Coord o = origin.offsetBy(x, y, z);
          if (Leaf* leaf = acc.probeLeaf(o)) {
            tasks.push_back({o, true, leaf});
            continue;
          }
          const bool known = acc.isValueOn(o);
          const float value = known ? acc.getValue(o) : 0.0f;
          if (known && value <= min_lo) {
            ++stats.saturated_leaves;
            continue;
          }
          acc.addTile(1, o, std::max(value + miss, min_lo), true);
          ++stats.free_tiles;
        }
      }
    }
  };
  auto visit = [&](auto& self, const openvdb::Coord& origin, int size) -> void {
    const BlockKind kind = classifier.classify(origin, size);
    switch (kind) {
      case BlockKind::kSkip:
        return;
      case BlockKind::kFree:
        add_free(origin, size);
        return;
      case BlockKind::kFarEdge:
      case BlockKind::kEdge:
      case BlockKind::kSurface:
        if (size == kLeafDim) {
          const bool coarse =
              kind == BlockKind::kFarEdge && hits.mask.probeConstLeaf(origin) == nullptr;
          tasks.push_back({origin, false, nullptr, coarse});
          return;
        }
        const int half = size / 2;
        for (int i = 0; i < 8; ++i) {
          self(self, origin.offsetBy((i & 1) * half, ((i >> 1) & 1) * half, ((i >> 2) & 1) * half),
               half);
        }
    }
  };
  const Eigen::Vector3d lo = frustum.min() / v, hi = frustum.max() / v;
  for (int x = block_floor(lo.x()); x <= hi.x(); x += kTopBlock) {
    for (int y = block_floor(lo.y()); y <= hi.y(); y += kTopBlock) {
      for (int z = block_floor(lo.z()); z <= hi.z(); z += kTopBlock) {
        visit(visit, openvdb::Coord(x, y, z), kTopBlock);
      }
    }
  }
  for (LeafTask& t : tasks) {
    if (t.leaf == nullptr) t.leaf = acc.touchLeaf(t.origin);
    (t.free ? stats.free_leaves : stats.surface_leaves) += 1;
  }

  // Update the leaves in parallel; each task owns its leaf.
  const auto hit = static_cast<float>(config_.hit_log_odds);
  const auto max_lo = static_cast<float>(config_.max_log_odds);
  std::vector<char> saturated(tasks.size(), 0);
  const Eigen::Matrix3d step_C = proj.R_camera_pen * v;  // C offset per index step along x, y, z
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, tasks.size()), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i) {
          Leaf& leaf = *tasks[i].leaf;
          float* values = leaf.buffer().data();
          if (tasks[i].free) {
            bool all_min = true;
            for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) {
              values[n] = std::max(values[n] + miss, min_lo);
              all_min &= values[n] <= min_lo;
            }
            leaf.setValuesOn();
            saturated[i] = all_min;
            continue;
          }
          const openvdb::Coord& o = tasks[i].origin;
          const auto* hit_leaf = hits.mask.probeConstLeaf(o);
          const Eigen::Vector3d c0 =
              proj.R_camera_pen * (Eigen::Vector3d(o.x(), o.y(), o.z()) * v) + proj.t_camera_pen;
          // Whole sub-blocks (8, 4, 2 voxels per side) are decided from their own footprint
          // where they lie wholly in front of or behind every depth in it: a voxel's footprint
          // lies inside its block's, so its pyramid blocks lie in the block's, its near is at
          // least the block's near and its far at most the block's far. The voxels left
          // undecided are tested one by one; the result is the same as testing every voxel.
          std::array<Decision, Leaf::SIZE> decided;
          decided.fill(Decision::kUndecided);
          auto fill = [&](int x0, int y0, int z0, int size, Decision d) {
            for (int x = x0; x < x0 + size; ++x) {
              for (int y = y0; y < y0 + size; ++y) {
                for (int z = z0; z < z0 + size; ++z) {
                  decided[Leaf::coordToOffset(o.offsetBy(x, y, z))] = d;
                }
              }
            }
          };
          auto decide = [&](auto& self, int x0, int y0, int z0, int size) -> void {
            const double mid = 0.5 * (size - 1);
            const Projection::Footprint f = proj.footprint(
                c0 + step_C * Eigen::Vector3d(x0 + mid, y0 + mid, z0 + mid), 0.5 * size * v);
            if (f.z_far <= 0) return fill(x0, y0, z0, size, Decision::kNotFree);
            if (f.z_near > 0) {
              if (proj.misses_image(f)) return fill(x0, y0, z0, size, Decision::kNotFree);
              const DepthPyramid::Bounds b = pyramid_.query(pixel_of(f.u_min), pixel_of(f.v_min),
                                                            pixel_of(f.u_max), pixel_of(f.v_max));
              if (f.z_near > b.far_m) return fill(x0, y0, z0, size, Decision::kNotFree);
              if (proj.inside_image(f) && f.z_far <= config_.max_range_m &&
                  f.z_far < b.near_m - config_.free_margin_m) {
                return fill(x0, y0, z0, size, Decision::kFree);
              }
            }
            if (size == 2) return;
            const int half = size / 2;
            for (int k = 0; k < 8; ++k) {
              self(self, x0 + (k & 1) * half, y0 + ((k >> 1) & 1) * half,
                   z0 + ((k >> 2) & 1) * half, half);
            }
          };
          decide(decide, 0, 0, 0, kLeafDim);
          bool all_min = true;
          for (int ix = 0; ix < kLeafDim; ++ix) {
            for (int iy = 0; iy < kLeafDim; ++iy) {
              Eigen::Vector3d c = c0 + step_C.col(0) * ix + step_C.col(1) * iy;
              for (int iz = 0; iz < kLeafDim; ++iz, c += step_C.col(2)) {
                const openvdb::Index n = Leaf::coordToOffset(o.offsetBy(ix, iy, iz));
                if (hit_leaf != nullptr && hit_leaf->isValueOn(n)) {
                  values[n] = std::min(values[n] + hit, max_lo);
                  leaf.setValueOn(n);
                  all_min = false;
                  continue;
                }
                bool is_free = decided[n] == Decision::kFree;
                if (decided[n] == Decision::kUndecided && !tasks[i].coarse) {
                  const Projection::Footprint f = proj.footprint(c, 0.5 * v);
                  is_free = f.z_near > 0 && f.z_far <= config_.max_range_m && proj.inside_image(f);
                  if (is_free) {
                    const DepthPyramid::Bounds b = pyramid_.query(
                        pixel_of(f.u_min), pixel_of(f.v_min), pixel_of(f.u_max), pixel_of(f.v_max));
                    is_free = f.z_far < b.near_m - config_.free_margin_m;
                  }
                }
                if (is_free) {
                  values[n] = std::max(values[n] + miss, min_lo);
                  leaf.setValueOn(n);
                }
                all_min &= leaf.isValueOn(n) && values[n] <= min_lo;
              }
            }
          }
          saturated[i] = all_min;
        }
      });
  for (size_t i = 0; i < tasks.size(); ++i) {
    if (saturated[i]) acc.addTile(1, tasks[i].origin, min_lo, true);
  }
  return stats;
}

}  // namespace pensight::mapping
