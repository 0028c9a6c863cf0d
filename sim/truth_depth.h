#pragma once
// Ground-truth depth images straight from the world's net geometry, by the rule of the renderer's
// depth output (sim/render_cpu.h): the z-depth of the net seen by each pixel's centre ray, 0 where
// the ray meets the water surface first or the net lies beyond the visible range. Fish are not
// drawn. Much cheaper than rendering, for mapping tests and benchmarks over whole sequences.
#include <Eigen/Geometry>

#include "core/camera.h"
#include "core/image.h"
#include "sim/net_geometry.h"
#include "sim/scenario.h"

namespace pensight::sim {

// Every `stride`-th pixel per axis is traced; the others are 0 (no measurement).
ImageF32 truth_depth(const Scenario& s, const NetGeometry& net, const PinholeCamera& cam,
                     const Eigen::Isometry3d& T_pen_camera, int stride = 1);

}  // namespace pensight::sim
