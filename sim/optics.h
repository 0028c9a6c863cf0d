#pragma once
// The camera as it is in the sea, applied to a rendered frame's noise-free radiance: water
// colour, thin-lens defocus, motion blur over the exposure, sensor noise, rounding and a JPEG
// round trip, in that order (docs/sim.md, "Optics"). Both renderers hand over their radiance and
// share this CPU post-process; with every optics key at its default they round and add noise
// themselves, as before, and this file only lends them the sensor model (sensor_value).
#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "sim/frame_state.h"
#include "sim/render_cpu.h"

namespace pensight::sim {

// True when any optics key is on (defocus, motion blur, colour or JPEG).
bool optics_enabled(const CameraConfig& c);

// Thin-lens blur-circle diameter in pixels of a point at z-depth depth_m (<= 0: far away, the
// limit 1/d = 0) with the lens focused at c.focus_distance_m (0: pinhole, always 0).
double blur_circle_px(const CameraConfig& c, double depth_m);
// Blur circles are cut at this diameter (a frame this far out of focus shows nothing anyway).
inline constexpr double kMaxBlurCircle_px = 41;
// Each pixel averaged over a disc of its own blur circle (from its depth; 0 = far away).
ImageF32 defocus(const ImageF32& grey, const ImageF32& depth_m, const CameraConfig& c);

// The camera's velocity in its own frame C at the frame's time.
struct CameraMotion {
  Eigen::Vector3d velocity_c_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_c_radps = Eigen::Vector3d::Zero();
};
CameraMotion camera_motion(const Scenario& s, const FrameState& f);
// Image velocity (px/s) of the still point seen at pixel (x, y) at z-depth depth_m (<= 0: far
// away, only the rotation moves it); distortion is ignored.
Eigen::Vector2d image_velocity_pxps(const PinholeCamera& cam, const CameraMotion& m, double x_px,
                                    double y_px, double depth_m);
// Each pixel averaged along its image motion over the exposure, centred on the frame's time.
ImageF32 motion_blur(const ImageF32& grey, const ImageF32& depth_m, const PinholeCamera& cam,
                     const CameraMotion& m, double exposure_time_s);

// Beam attenuation of red, green and blue as multiples of water.attenuation_per_m (the grey
// model's value is green's), and the colour of the veiling light (luma 1).
inline constexpr std::array<double, 3> kChannelAttenuation = {2.4, 1.0, 1.4};
std::array<double, 3> veil_colour();
// The grey radiance split into red, green, blue: the object's share is attenuated per channel
// over the pixel's path length (from depth_m), the veil takes the water's colour. Pixels
// without depth (open water, surface, fish) take the veil's colour.
std::array<ImageF32, 3> water_colour(const ImageF32& grey, const ImageF32& depth_m,
                                     const Scenario& s, const FrameState& f);

// The sensor: Gaussian read and shot noise (hashed per pixel, frame and channel) and rounding
// to 0..255; the renderers' model, so channel 0 draws what the grey frame draws.
uint32_t noise_frame_key(const Scenario& s, int frame);
uint8_t sensor_value(double grey, uint32_t pixel, uint32_t frame_key, uint32_t channel,
                     const CameraConfig& c, bool noise);

// JPEG-encoded at `quality` (1-100) and decoded again, so the frame carries the block artefacts.
ImageU8 jpeg_round_trip(const ImageU8& image, int quality);
ImageRgb8 jpeg_round_trip(const ImageRgb8& image, int quality);

// The whole chain: r.radiance (and r.depth_m) -> r.image, or r.image_rgb with camera.colour.
void apply_optics(const Scenario& s, const FrameState& f, const RenderOptions& o, RenderedFrame& r);

}  // namespace pensight::sim
