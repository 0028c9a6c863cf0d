// The camera's optics (sim/optics.h): the thin-lens blur circle against the lens equation, a
// point blurred into a disc of that diameter, a known translation smeared by its predicted
// length, the camera's velocity from the trajectory, JPEG artefacts that keep the mean, colour
// frames whose red fades fastest with distance, and the defaults leaving the frame unchanged.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>

#include "core/error.h"
#include "pipeline/dataset/png_io.h"
#include "sim/frame_state.h"
#include "sim/generate.h"
#include "sim/optics.h"
#include "sim/render_cpu.h"
#include "tests/sim/sim_test_scenes.h"

namespace pensight::sim {
namespace {

// Centroid and second moments of an image (a blurred point).
struct Moments {
  double mean_x = 0, mean_y = 0, var_x = 0, var_y = 0, total = 0;
};

Moments moments(const ImageF32& img) {
  Moments m;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double w = img.at(x, y);
      m.total += w;
      m.mean_x += w * x;
      m.mean_y += w * y;
    }
  }
  m.mean_x /= m.total;
  m.mean_y /= m.total;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double w = img.at(x, y) / m.total;
      m.var_x += w * (x - m.mean_x) * (x - m.mean_x);
      m.var_y += w * (y - m.mean_y) * (y - m.mean_y);
    }
  }
  return m;
}

double mean(const ImageU8& img) {
  double sum = 0;
  for (const uint8_t v : img.pixels) sum += v;
  return sum / static_cast<double>(img.pixels.size());
}

CameraConfig lens(double focus_m, double f_number, double pitch_m) {
  CameraConfig c;
  c.calibration.camera.fx_px = c.calibration.camera.fy_px = 462;
  c.focus_distance_m = focus_m;
  c.f_number = f_number;
  c.pixel_pitch_m = pitch_m;
  return c;
}

TEST(Optics, BlurCircleFollowsTheLensEquation) {
  const CameraConfig c = lens(1.2, 2.0, 20e-6);
  const double f = 462 * 20e-6, aperture = f / 2.0;
  auto image_distance = [&](double d) { return 1 / (1 / f - 1 / d); };
  for (const double d : {0.3, 0.8, 1.2, 2.0, 10.0}) {
    // The sensor sits where the focus distance images; a point at d converges at v, so its cone
    // of diameter A is A |v - v_f| / v wide on the sensor.
    const double v = image_distance(d), v_f = image_distance(1.2);
    const double expected_px = aperture * std::abs(v - v_f) / v / 20e-6;
    EXPECT_NEAR(blur_circle_px(c, d), expected_px, 1e-9 * (1 + expected_px)) << d;
  }
  EXPECT_EQ(blur_circle_px(c, 1.2), 0.0);
  // Far away (no depth) is the limit d -> infinity.
  EXPECT_NEAR(blur_circle_px(c, 0), blur_circle_px(c, 1e12), 1e-6);
  EXPECT_EQ(blur_circle_px(lens(0, 2.0, 20e-6), 0.5), 0.0);  // pinhole
}

TEST(Optics, DefocusSpreadsAPointIntoTheBlurCircle) {
  const CameraConfig c = lens(2.0, 1.0, 20e-6);
  const double depth = 0.3, predicted = blur_circle_px(c, depth);
  ASSERT_GT(predicted, 8);
  ASSERT_LT(predicted, 20);
  ImageF32 img(81, 81), depth_m(81, 81, static_cast<float>(depth));
  img.at(40, 40) = 1000;
  const ImageF32 out = defocus(img, depth_m, c);
  const Moments m = moments(out);
  // A uniform disc of diameter c has E[r^2] = c^2 / 8.
  const double measured = std::sqrt(8 * (m.var_x + m.var_y));
  std::printf("  blur circle: predicted %.3f px, measured %.3f px\n", predicted, measured);
  // Measured 12.24 vs 12.15 px predicted (the anti-aliased rim adds a little); bound 0.25 px.
  EXPECT_NEAR(measured, predicted, 0.25);
  EXPECT_NEAR(m.total, 1000, 1e-3);  // uniform depth: every pixel has the same kernel
  EXPECT_NEAR(m.mean_x, 40, 1e-9);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      if (std::hypot(x - 40, y - 40) > predicted / 2 + 0.5) {
        EXPECT_EQ(out.at(x, y), 0.0f);
      }
    }
  }
  // In focus nothing moves.
  const ImageF32 sharp = defocus(img, ImageF32(81, 81, 2.0f), c);
  EXPECT_EQ(sharp.pixels, img.pixels);
}

TEST(Optics, MotionBlurSmearsAKnownTranslationByItsLength) {
  PinholeCamera cam;
  cam.width_px = 81;
  cam.height_px = 41;
  cam.fx_px = cam.fy_px = 462;
  cam.cx_px = 40;
  cam.cy_px = 20;
  CameraMotion motion;
  motion.velocity_c_mps = {0.4, 0, 0};
  const double depth = 1.0, exposure = 0.1;
  const double predicted = cam.fx_px * 0.4 * exposure / depth;  // 18.48 px
  ImageF32 img(81, 41), depth_m(81, 41, static_cast<float>(depth));
  img.at(40, 20) = 1000;
  const Moments m = moments(motion_blur(img, depth_m, cam, motion, exposure));
  // A uniform segment of length L has variance L^2 / 12.
  const double measured = std::sqrt(12 * m.var_x);
  std::printf("  motion smear: predicted %.3f px, measured %.3f px\n", predicted, measured);
  // Measured 18.50 vs 18.48 px: n samples at the midpoints of equal parts plus the bilinear
  // spread; bound 0.3 px.
  EXPECT_NEAR(measured, predicted, 0.3);
  EXPECT_NEAR(m.mean_x, 40, 0.05);  // centred on the frame's time
  EXPECT_LT(m.var_y, 1e-9);         // horizontal motion only
  // Twice as far, half the smear; far away (no depth) none from a translation.
  EXPECT_NEAR(image_velocity_pxps(cam, motion, 40, 20, 2.0).x(), -462 * 0.2, 1e-9);
  EXPECT_EQ(image_velocity_pxps(cam, motion, 40, 20, 0.0).norm(), 0.0);
  // A pan to the right (about camera y) moves the image left by fx * w.
  CameraMotion pan;
  pan.angular_velocity_c_radps = {0, 0.1, 0};
  EXPECT_NEAR(image_velocity_pxps(cam, pan, 40, 20, 0.0).x(), -462 * 0.1, 1e-9);
}

TEST(Optics, CameraMotionComesFromTheTrajectory) {
  // Along a 12 m pen's net at a constant 0.3 m/s, 0.8 m off the net, facing it: the body turns
  // at 0.3 / 12 rad/s about its z (down) axis, the camera moves right (its x) at the body's
  // 0.3 * 11.2 / 12 m/s plus the turn times its 0.3 m lever arm.
  const Scenario s = parse_scenario(
      "trajectory:\n  waypoints:\n"
      "    - {t_s: 0, along_m: 0, net_distance_m: 0.8, depth_m: 3}\n"
      "    - {t_s: 10, along_m: 3, net_distance_m: 0.8, depth_m: 3}\n",
      "motion.yaml");
  const CameraMotion m = camera_motion(s, frame_state(s, 20));
  const double yaw_rate = 0.3 / 12;
  EXPECT_NEAR(m.velocity_c_mps.x(), 0.3 * 11.2 / 12 + yaw_rate * 0.3, 1e-6);
  EXPECT_NEAR(m.velocity_c_mps.y(), 0, 1e-6);
  EXPECT_NEAR(m.velocity_c_mps.z(), 0, 1e-6);
  EXPECT_NEAR(m.angular_velocity_c_radps.y(), yaw_rate, 1e-6);
  EXPECT_NEAR(m.angular_velocity_c_radps.x(), 0, 1e-9);
  EXPECT_NEAR(m.angular_velocity_c_radps.z(), 0, 1e-9);
}

TEST(Optics, JpegChangesTheImageButKeepsItsMean) {
  const Scenario s = testing::one_pose({.net_distance_m = 1.0});
  Scenario q =
      testing::one_pose({.net_distance_m = 1.0}, 180, 135,
                        "{shape: cylinder, radius_m: 12, depth_m: 15}", "", ", jpeg_quality: 40");
  const NetGeometry net(s.pen, s.net);
  const RenderedFrame plain = render_cpu(s, net, frame_state(s, 0));
  const RenderedFrame jpeg = render_cpu(q, net, frame_state(q, 0));
  size_t changed = 0;
  for (size_t i = 0; i < plain.image.pixels.size(); ++i) {
    changed += plain.image.pixels[i] != jpeg.image.pixels[i];
  }
  std::printf("  jpeg 40: %zu of %zu pixels changed, mean %.3f -> %.3f\n", changed,
              plain.image.pixels.size(), mean(plain.image), mean(jpeg.image));
  // Measured: 94 % of the pixels change, the mean by 0.065 grey levels; bounds 30 % and 0.5.
  EXPECT_GT(changed, plain.image.pixels.size() * 3 / 10);
  EXPECT_NEAR(mean(jpeg.image), mean(plain.image), 0.5);
}

TEST(Optics, ColourFramesLoseRedFastestWithDistance) {
  auto red_over_green = [](double net_distance_m) {
    const Scenario s =
        testing::one_pose({.net_distance_m = net_distance_m}, 180, 135,
                          "{shape: cylinder, radius_m: 12, depth_m: 15}", "", ", colour: true");
    const NetGeometry net(s.pen, s.net);
    const RenderedFrame r = render_cpu(s, net, frame_state(s, 0), {.noise = false});
    EXPECT_TRUE(r.image.empty());
    EXPECT_EQ(r.image_rgb.width, 180);
    EXPECT_EQ(r.image_rgb.height, 135);
    double red = 0, green = 0, blue = 0;
    for (const auto& p : r.image_rgb.pixels) {
      red += p[0];
      green += p[1];
      blue += p[2];
    }
    EXPECT_GT(green, red);  // blue-green water
    EXPECT_GT(blue, red);
    return red / green;
  };
  const double near = red_over_green(0.6), far = red_over_green(3.0);
  std::printf("  red / green: %.3f at 0.3 m, %.3f at 2.7 m\n", near, far);
  // Measured 0.875 and 0.405; bound: at least 20 % less red far away.
  EXPECT_LT(far, 0.8 * near);
}

TEST(Optics, WaterColourKeepsANearObjectGrey) {
  // At zero path length the object's radiance passes unchanged in every channel.
  const Scenario s = testing::one_pose({.net_distance_m = 1.0});
  const FrameState f = frame_state(s, 0);
  ImageF32 grey(180, 135, 120.0f), depth(180, 135, 1e-6f);
  const auto rgb = water_colour(grey, depth, s, f);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rgb[k].at(90, 67), 120.0f, 0.01f) << k;
  // Without depth (open water) a pixel takes the veil's colour at its brightness.
  const auto veil = water_colour(grey, ImageF32(180, 135), s, f);
  const auto tint = veil_colour();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(veil[k].at(5, 5), 120 * tint[k], 1e-3) << k;
  EXPECT_NEAR(0.299 * tint[0] + 0.587 * tint[1] + 0.114 * tint[2], 1.0, 1e-12);
}

TEST(Optics, DefaultsLeaveTheFrameUnchanged) {
  const Scenario s = testing::one_pose({.net_distance_m = 1.0});
  EXPECT_FALSE(optics_enabled(s.camera));
  const Scenario explicit_defaults = testing::one_pose(
      {.net_distance_m = 1.0}, 180, 135, "{shape: cylinder, radius_m: 12, depth_m: 15}", "",
      ", focus_distance_m: 0, f_number: 2.8, pixel_pitch_m: 3.45e-6, exposure_time_s: 0, "
      "colour: false, jpeg_quality: 0");
  const NetGeometry net(s.pen, s.net);
  const RenderedFrame a = render_cpu(s, net, frame_state(s, 2));
  const RenderedFrame b = render_cpu(explicit_defaults, net, frame_state(explicit_defaults, 2));
  EXPECT_TRUE(a.radiance.empty());
  EXPECT_EQ(a.image.pixels, b.image.pixels);
  // The optics' sensor on the renderer's radiance is the renderer's own sensor: only the float
  // rounding of the handed-over radiance may flip a rounding (measured: none of 24300 pixels).
  RenderedFrame raw = render_cpu(s, net, frame_state(s, 2), {.radiance_only = true});
  ASSERT_TRUE(raw.image.empty());
  apply_optics(s, frame_state(s, 2), {}, raw);
  size_t differ = 0;
  for (size_t i = 0; i < a.image.pixels.size(); ++i) {
    EXPECT_LE(std::abs(a.image.pixels[i] - raw.image.pixels[i]), 1);
    differ += a.image.pixels[i] != raw.image.pixels[i];
  }
  std::printf("  radiance handed over: %zu of %zu pixels differ by one level\n", differ,
              a.image.pixels.size());
  EXPECT_LE(differ, a.image.pixels.size() / 1000);
}

TEST(Optics, ScenarioKeysAreChecked) {
  auto parse = [](const std::string& camera) {
    return parse_scenario("camera: {" + camera +
                              "}\ntrajectory:\n  waypoints:\n"
                              "    - {t_s: 0, net_distance_m: 1, depth_m: 3}\n",
                          "keys.yaml");
  };
  const Scenario s = parse(
      "focus_distance_m: 1.5, f_number: 2, pixel_pitch_m: 5e-6, exposure_time_s: 0.02, "
      "colour: true, jpeg_quality: 70");
  EXPECT_EQ(s.camera.focus_distance_m, 1.5);
  EXPECT_EQ(s.camera.f_number, 2);
  EXPECT_EQ(s.camera.pixel_pitch_m, 5e-6);
  EXPECT_EQ(s.camera.exposure_time_s, 0.02);
  EXPECT_TRUE(s.camera.colour);
  EXPECT_EQ(s.camera.jpeg_quality, 70);
  EXPECT_TRUE(optics_enabled(s.camera));
  for (const std::string bad :
       {"jpeg_quality: 101", "jpeg_quality: -1", "f_number: 0.1", "pixel_pitch_m: 1e-3",
        "focus_distance_m: -1", "focus_distance_m: 0.002", "exposure_time_s: 0.2"}) {
    try {
      parse(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& e) {
      const std::string key = bad.substr(0, bad.find(':'));
      EXPECT_NE(std::string(e.what()).find("camera." + key), std::string::npos) << e.what();
    }
  }
}

TEST(Optics, ColourDatasetIsWrittenInRgbAndReadAsGrey) {
  Scenario s = testing::one_pose({.net_distance_m = 1.0}, 96, 72,
                                 "{shape: cylinder, radius_m: 12, depth_m: 15}", "",
                                 ", colour: true, jpeg_quality: 80");
  const auto dir = std::filesystem::temp_directory_path() /
                   ("pensight_optics_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  auto renderer = make_cpu_renderer(s, {});
  generate_dataset(s, *renderer, dir);
  const auto png = dir / "cam0" / "data" / (std::to_string(s.frame_time_ns(0)) + ".png");
  const ImageU8 grey = read_png_grey8(png, 96, 72);
  const RenderedFrame r = render_cpu(s, NetGeometry(s.pen, s.net), frame_state(s, 0));
  // The reader's luma of the written RGB pixels (OpenCV rounds its fixed-point weights).
  double worst = 0;
  for (size_t i = 0; i < grey.pixels.size(); ++i) {
    const auto& p = r.image_rgb.pixels[i];
    worst =
        std::max(worst, std::abs(grey.pixels[i] - (0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2])));
  }
  EXPECT_LT(worst, 1.0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pensight::sim
