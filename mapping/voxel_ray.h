#pragma once
// Voxel traversal along a ray (Amanatides & Woo 1987, "A fast voxel traversal algorithm for ray
// tracing"), in index space: voxel c spans [c - 0.5, c + 0.5) per axis. One step per voxel face
// crossed, no allocation.
#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>

namespace pensight::mapping {

// Visits the voxels that origin + t * dir crosses for t in [0, t_max], in order, calling
// visit(coord, t_enter, t_exit); stops early when visit returns false. dir must be non-zero.
template <class Visit>
void traverse_voxels(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                     Visit&& visit) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  openvdb::Coord c;
  int step[3];
  double t_next[3], t_delta[3];
  for (int a = 0; a < 3; ++a) {
    const double p = origin[a] + 0.5;  // voxel c spans [c, c + 1) in this shifted space
    c[a] = static_cast<int>(std::floor(p));
    if (dir[a] > 0) {
      step[a] = 1;
      t_delta[a] = 1.0 / dir[a];
      t_next[a] = (c[a] + 1 - p) * t_delta[a];
    } else if (dir[a] < 0) {
      step[a] = -1;
      t_delta[a] = -1.0 / dir[a];
      t_next[a] = (p - c[a]) * t_delta[a];
    } else {
      step[a] = 0;
      t_delta[a] = kInf;
      t_next[a] = kInf;
    }
  }
  double t = 0;
  while (t <= t_max) {
    const int a =
        t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    const double t_exit = std::min(t_next[a], t_max);
    if (!visit(c, t, t_exit)) return;
    t = t_next[a];
    c[a] += step[a];
    t_next[a] += t_delta[a];
  }
}

}  // namespace pensight::mapping
