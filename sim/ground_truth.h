#pragma once
// Ground truth of the net relative to cam0 (dataset-format.md, groundtruth0/data.csv).
#include "core/dataset_types.h"
#include "pipeline/dataset/dataset_writer.h"
#include "sim/frame_state.h"
#include "sim/net_geometry.h"
#include "sim/net_mesh.h"
#include "sim/render_cpu.h"

namespace pensight::sim {

struct NetRelative {
  double d_net_m = kNaN;  // along +z_C to the first net point (NaN: the axis misses the net)
  double psi_net_rad = kNaN, pitch_net_rad = kNaN;
  Eigen::Vector3d m_C = Eigen::Vector3d::Constant(kNaN);  // net normal into the net, in C
};

// The optical axis against the net; the net counts as missed beyond net_visible_range_m or
// behind the water surface, exactly as for the depth image.
NetRelative net_relative(const Scenario& s, const NetGeometry& net,
                         const Eigen::Isometry3d& T_pen_camera);

// The mesh at the optical axis's net hit (groundtruth0/mesh.csv), by the same rule as
// net_relative; opening angle and stretch NaN where the axis misses.
MeshTruthRow mesh_truth_row(const Scenario& s, const NetGeometry& net, const NetLattice& lattice,
                            const FrameState& f);

// The groundtruth0 row of a rendered frame (net_fraction from its depth image).
GroundTruthRow ground_truth_row(const Scenario& s, const NetGeometry& net, const FrameState& f,
                                const ImageF32& depth_m);

}  // namespace pensight::sim
