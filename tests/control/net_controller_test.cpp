#include "control/net_controller.h"

#include "control/stick_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pensight::control {
namespace {

// A planar stand-in for the vehicle (the 6-DOF model is tested in tests/vehicle): surge and
// sway with the published added mass and damping, yaw rate following the stick's demand with a
// 0.2 s lag, depth following the climb demand. The net is the plane X = 0, the vehicle at X = -d
// facing it at heading psi (0: squarely, > 0 turned right, as psi_net); the current flows along X.
struct Plant {
  double X = -1.0, Y = 0, psi = 0, depth = 3.0;
  double u = 0, v = 0, r = 0;
  double current_x_mps = 0;

  double d_net() const { return -X; }

  void step(const ControlOutput& c, const VehicleModel& m, double dt) {
    const double cu = current_x_mps * std::cos(psi), cv = -current_x_mps * std::sin(psi);
    const double ur = u - cu, vr = v - cv;
    const Eigen::Vector2d f = horizontal_force_n(m, c.x, c.y);
    const double fx = f.x() - (13.7 * ur + 141 * ur * std::abs(ur));
    const double fy = f.y() - 217 * vr * std::abs(vr);
    u += dt * fx / (13.5 + 6.36);
    v += dt * fy / (13.5 + 7.12);
    r += dt * (c.r * m.full_stick_yaw_rate_radps - r) / 0.2;
    psi += dt * r;
    X += dt * (u * std::cos(psi) - v * std::sin(psi));
    Y += dt * (u * std::sin(psi) + v * std::cos(psi));
    depth -= dt * (c.z - 0.5) * 2 * m.full_stick_climb_rate_mps;
  }
};

struct Trace {
  std::vector<double> t_s, d_m, psi_rad, y_m;
  std::vector<ControlOutput> out;
};

// 10 Hz control, DVL at 4 Hz, plant at 200 Hz. `pose_ok(t)` and `dvl_ok(t)` cut the sensors.
template <typename PoseOk, typename DvlOk>
Trace simulate(NetController& ctl, Plant& p, double seconds, PoseOk pose_ok, DvlOk dvl_ok,
               uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 1);
  Trace run;
  const int64_t step_ns = 100'000'000;
  ControlOutput c;
  for (int k = 0; k * 0.1 < seconds; ++k) {
    const int64_t t_ns = k * step_ns;
    const double t = k * 0.1;
    if (pose_ok(t)) ctl.on_pose(t_ns, p.d_net() + 0.003 * noise(rng), p.psi + 0.005 * noise(rng));
    if (k % 5 == 0 || k % 5 == 2) {  // 4 Hz, not quite evenly, like a real DVL against a camera
      if (dvl_ok(t)) ctl.on_dvl(t_ns, {p.u + 0.005 * noise(rng), p.v + 0.005 * noise(rng), 0});
    }
    ctl.on_depth(t_ns, p.depth + 0.01 * noise(rng));
    c = ctl.update(t_ns);
    for (int i = 0; i < 20; ++i) p.step(c, ctl.config().vehicle, 0.005);
    run.t_s.push_back(t);
    run.d_m.push_back(p.d_net());
    run.psi_rad.push_back(p.psi);
    run.y_m.push_back(p.Y);
    run.out.push_back(c);
  }
  return run;
}

auto always = [](double) { return true; };

double rms_error(const Trace& r, double from_s, double ref) {
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < r.t_s.size(); ++i) {
    if (r.t_s[i] < from_s) continue;
    sum += (r.d_m[i] - ref) * (r.d_m[i] - ref);
    ++n;
  }
  return std::sqrt(sum / n);
}

ControlConfig hold(double d_ref, VelocityStrategy s) {
  ControlConfig c;
  c.strategy = s;
  c.legs = {Leg{.d_ref_m = d_ref}};
  return c;
}

// Start-up: armed in depth hold; without the DVL's feedback the sticks are neutral, with it the
// velocity loops hold the vehicle still (here, at rest, nearly neutral).
TEST(NetController, StartsArmedInDepthHoldHoldingStill) {
  for (const auto s : {VelocityStrategy::kOpenLoop, VelocityStrategy::kDvlFeedback}) {
    NetController ctl(hold(0.5, s));
    Plant p;
    const Trace r = simulate(ctl, p, 1.9, always, always);
    for (const ControlOutput& c : r.out) {
      EXPECT_EQ(c.state, ControlState::kStartup);
      if (s == VelocityStrategy::kOpenLoop) {
        EXPECT_EQ(c.x, 0);
        EXPECT_EQ(c.y, 0);
      }
      EXPECT_LT(std::abs(c.x) + std::abs(c.y), 0.3);
      EXPECT_EQ(c.r, 0);
      EXPECT_EQ(c.z, 0.5);
      EXPECT_TRUE(c.arm && c.depth_hold);
    }
    EXPECT_LT(std::abs(p.X + 1.0), 0.01);
  }
}

// The published gains on this plant: a 0.5 m step settles, the heading lines up, and the DVL
// loop's integral takes out a steady current the open loop leaves as an offset.
TEST(NetController, HoldsTheDistanceAndFacesTheNet) {
  for (const auto s : {VelocityStrategy::kDvlFeedback, VelocityStrategy::kOpenLoop}) {
    NetController ctl(hold(0.5, s));
    Plant p;
    p.psi = 0.2;
    const Trace r = simulate(ctl, p, 40, always, always);
    EXPECT_LT(rms_error(r, 20, 0.5), 0.01) << to_string(s);
    EXPECT_LT(std::abs(r.psi_rad.back()), 0.02) << to_string(s);
    EXPECT_NEAR(p.depth, 3.0, 0.05);
  }
  NetController dvl(hold(0.5, VelocityStrategy::kDvlFeedback));
  NetController open(hold(0.5, VelocityStrategy::kOpenLoop));
  Plant pd, po;
  pd.current_x_mps = po.current_x_mps = 0.1;  // into the net
  const double e_dvl = rms_error(simulate(dvl, pd, 60, always, always), 40, 0.5);
  const double e_open = rms_error(simulate(open, po, 60, always, always), 40, 0.5);
  EXPECT_LT(e_dvl, 0.02);  // 1.0 cm here (gcc and clang differ in the last digits)
  EXPECT_GT(e_open, 2 * e_dvl);
}

// The states and their counters; the distance kept on the 6-DOF vehicle is vehicle_loop_test's.
TEST(NetController, LostPerceptionHoldsThenBacksOffAndRecovers) {
  NetController ctl(hold(0.5, VelocityStrategy::kDvlFeedback));
  Plant p;
  p.current_x_mps = 0.2;  // pushing the vehicle into the net
  const auto lost = [](double t) { return t < 20 || t >= 23.5; };
  const Trace r = simulate(ctl, p, 40, lost, always);
  double nearest = 1e9;
  for (double d : r.d_m) nearest = std::min(nearest, d);
  EXPECT_GT(nearest, 0.2);
  EXPECT_GT(ctl.counters().hold_steps, 20);
  EXPECT_GT(ctl.counters().backoff_steps, 0);
  EXPECT_EQ(ctl.counters().recoveries, 1);
  bool saw_backoff = false;
  for (const ControlOutput& c : r.out) saw_backoff |= c.state == ControlState::kBackOff;
  EXPECT_TRUE(saw_backoff);
}

// The surge speed reference of the step after a 2 cm jump in the pose (below the speed limit),
// given with `quality`: before it, 3 s of poses at the reference distance (1 s of tracking), then
// `gap_s` without one.
double surge_after_a_jump(double quality, double gap_s) {
  NetController ctl(hold(1.0, VelocityStrategy::kDvlFeedback));
  int64_t t_ns = 0;
  for (; t_ns < 3'000'000'000; t_ns += 100'000'000) {
    ctl.on_pose(t_ns, 1.0, 0.0);
    ctl.on_dvl(t_ns, Eigen::Vector3d::Zero());
    ctl.update(t_ns);
  }
  t_ns += static_cast<int64_t>(gap_s * 1e9);
  ctl.on_pose(t_ns, 1.02, 0.0, quality);
  ctl.on_dvl(t_ns, Eigen::Vector3d::Zero());
  const ControlOutput out = ctl.update(t_ns);
  EXPECT_EQ(out.state, ControlState::kTracking);
  return out.u_ref_mps;
}

// A pose of low quality moves the distance the loops act on by pose_trust() of the jump (0.1 at
// quality 0.05), so it steers a tenth as much; after a timeout there is nothing to blend with and
// it is taken whole.
TEST(NetController, ALowQualityPoseSteersLess) {
  const double trusted = surge_after_a_jump(1.0, 0);
  ASSERT_GT(trusted, 0.01);
  EXPECT_NEAR(surge_after_a_jump(0.05, 0), 0.1 * trusted, 0.02 * trusted);
  EXPECT_NEAR(surge_after_a_jump(0.25, 0), 0.5 * trusted, 0.02 * trusted);
  EXPECT_EQ(surge_after_a_jump(0.05, 1.0), surge_after_a_jump(1.0, 1.0));
}

TEST(NetController, DvlDropoutFallsBackToTheOpenLoop) {
  ControlConfig c = hold(0.5, VelocityStrategy::kDvlFeedback);
  c.legs[0].sway_speed_mps = 0.1;
  NetController ctl(c);
  Plant p;
  const auto dvl = [](double t) { return t < 15 || t >= 25; };
  const Trace r = simulate(ctl, p, 35, always, dvl);
  int open = 0;
  for (const ControlOutput& o : r.out) open += o.strategy == VelocityStrategy::kOpenLoop;
  EXPECT_NEAR(open, 90, 5);  // 10 s less the 1 s timeout, at 10 Hz
  EXPECT_EQ(ctl.counters().open_loop_fallback_steps, open);
  EXPECT_LT(rms_error(r, 15, 0.5), 0.02);
  EXPECT_GT(r.y_m.back(), 2.5);  // kept moving along the net at about 0.1 m/s
}

TEST(NetController, LegsEndByLengthAndDuration) {
  ControlConfig c;
  c.legs = {Leg{.d_ref_m = 0.5, .sway_speed_mps = 0.2, .length_m = 2.0},
            Leg{.d_ref_m = 1.0, .sway_speed_mps = -0.2, .duration_s = 5.0}, Leg{.d_ref_m = 1.5}};
  NetController ctl(c);
  Plant p;
  p.X = -0.5;
  const Trace r = simulate(ctl, p, 40, always, always);
  double switch1 = -1, switch2 = -1;
  for (size_t i = 0; i < r.out.size(); ++i) {
    if (switch1 < 0 && r.out[i].leg == 1) switch1 = r.t_s[i];
    if (switch2 < 0 && r.out[i].leg == 2) switch2 = r.t_s[i];
  }
  EXPECT_NEAR(switch1, 2.0 + 2.0 / 0.2, 2.0);  // startup, then 2 m at about 0.2 m/s
  EXPECT_NEAR(switch2 - switch1, 5.0, 0.15);
  EXPECT_NEAR(p.d_net(), 1.5, 0.02);
}

}  // namespace
}  // namespace pensight::control
