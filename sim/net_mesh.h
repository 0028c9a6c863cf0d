#pragma once
// The net's mesh as a lattice in the net surface coordinates (u, v) of NetHit: knots at
// i b1 + j b2 with |b1| = |b2| = bar_length_m (the bar) and angle(b1, b2) = the opening angle; the
// twines are the lines through the knots parallel to b1 (family A) and to b2 (family B). The
// lattice lives in deformed coordinates x' = (u, v) + D(u, v), D a slow displacement field (as
// currents and weights deform a net), so the local opening angle and bar length vary. Shared by
// the CPU renderer, the ground truth and render_vk.cpp (which passes these numbers to the
// shader); docs/sim.md gives the model.
#include <Eigen/Core>
#include <array>

#include "sim/net_geometry.h"
#include "sim/scenario.h"

namespace pensight::sim {

// The mesh at a point of the net: what a detector should find there.
struct LocalMesh {
  MeshType type = MeshType::kSquare;
  double opening_angle_rad = 0;  // between the two local bars
  double stretch = 0;            // mean local bar length / bar_length_m - 1
};

// Whole-number closures around the pen: `period` stretched so that `count` of them fill the
// circumference (count 0 and period unchanged on a plane or the bottom).
struct Closure {
  double period = 0;
  int count = 0;
};

class NetLattice {
 public:
  // u_around: the wall's u around the pen (0: the net does not wrap); seed: the scenario's.
  NetLattice(const NetConfig& net, double u_around, uint64_t seed);

  // Step along u after which the undeformed lattice repeats exactly: bar_length_m for a square mesh
  // (b1 is horizontal), 2 bar_length_m sin(theta / 2) for a diamond (b1 - b2 is horizontal).
  static double closing_step(const NetConfig& net);

  // Unit normals of the twine families (family A: parallel to b1) and their spacing
  // bar_length_m sin(theta): the twine lines are q = n . x' = k * period.
  const Eigen::Vector2d& normal_a() const { return n_a_; }
  const Eigen::Vector2d& normal_b() const { return n_b_; }
  double period() const { return period_; }
  const Eigen::Vector2d& bar1() const { return b1_; }
  const Eigen::Vector2d& bar2() const { return b2_; }

  bool deformed() const { return s_ > 0 || g_ > 0; }
  // x' and dx'/dx at (u, v) on `part`; on the cylinder wall D fades out over deform_scale_m
  // before the azimuth seam so the lattice still closes around the pen.
  void deform(double u, double v, NetPart part, Eigen::Vector2d& x, Eigen::Matrix2d& J) const;

  // The local mesh at (u, v); u_scale = du/ds (NetGeometry::lattice_scale() on the wall).
  LocalMesh local_mesh(double u, double v, NetPart part, double u_scale) const;

  // Deformation constants for the shader: bisector (e_b), wavenumbers of the stretch and angle
  // modes, their amplitudes, the four phases, the fade length and u around the pen.
  const Eigen::Vector2d& bisector() const { return e_b_; }
  double k_stretch() const { return k_s_; }
  double k_angle() const { return k_g_; }
  double amp_stretch() const { return s_; }
  double amp_angle() const { return g_; }
  const std::array<double, 4>& phases() const { return phase_; }
  double fade_m() const { return fade_m_; }
  double u_around() const { return u_around_; }

  // Fouled patches: value noise above this threshold (soft, +-kPatchSoftness) is a patch, so
  // that the patches cover fouling_coverage of the net.
  double patch_threshold() const { return patch_threshold_; }
  // Clump noise cells (along u on the wall: closed around the pen) and the clumps' mean fill.
  const Closure& clump_cells_u() const { return clump_u_; }
  double clump_cell_v() const { return clump_v_; }
  double clump_mean() const { return clump_mean_; }
  // Ropes and seams along u (closed around the pen on the wall).
  const Closure& rope_u() const { return rope_u_; }
  const Closure& seam_u() const { return seam_u_; }
  // Mean coverage of a round knot (disc area / cell area), where the footprint hides it.
  double round_knot_mean() const { return knot_mean_; }
  // n_a . n_b, for the distance to the nearest knot from the two twine offsets.
  double normals_dot() const { return n_a_.dot(n_b_); }

 private:
  NetConfig net_;
  Eigen::Vector2d b1_, b2_, n_a_, n_b_, e_b_;
  double period_ = 0;
  double u_around_ = 0, fade_m_ = 0;
  double k_s_ = 0, k_g_ = 0, s_ = 0, g_ = 0;
  std::array<double, 4> phase_{};
  double patch_threshold_ = 2, clump_v_ = 0, clump_mean_ = 0, knot_mean_ = 0;
  Closure clump_u_, rope_u_, seam_u_;
};

// Patch edge softness in value-noise units, the clumps' threshold band and cell size (in
// bar_length_m), the thickening of fouled twines and the brightening of round knots: the constants
// of the look, shared with shaders/sim/render.comp.
inline constexpr double kPatchSoftness = 0.12;
inline constexpr double kClumpLo = 0.6, kClumpHi = 0.85, kClumpCellMeshes = 0.4;
inline constexpr double kClumpReach = 0.2;  // of the twine spacing, from the twine's edge
// Width x (1 + 1.5 patch) = 2.5 x in a patch, at most kFouledMaxWidth of the twine spacing
// (or the clean width, if wider).
inline constexpr double kFouledThickening = 1.5, kFouledMaxWidth = 0.45;
inline constexpr double kFouledAlbedo = 0.85, kFouledBrightening = 0.6;
inline constexpr double kKnotGain = 0.15;
inline constexpr double kSeamTwines = 3;  // a lacing line is this many twines wide

// Smooth value noise in [0, 1] on cells scale_u x scale_v; with wrap_u > 0 the cells repeat
// every wrap_u along u (around the cylinder). The shader has the same function.
double value_noise(double u, double v, double scale_u, double scale_v, int wrap_u, uint32_t seed);

double smoothstep(double lo, double hi, double x);

}  // namespace pensight::sim
