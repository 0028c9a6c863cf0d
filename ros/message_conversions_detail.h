#pragma once
// One ROS 1 message -> the dataset's sample types (dataset_types.h), shared by the bag reader
// (bag_dataset.h) and the ROS node (apps/ros/), so a bag replayed into the node and the same bag
// converted to a dataset give the pipeline the same inputs. Frames: ros_frames.h. Messages that
// cannot be used say why (a non-empty problem) instead of throwing, so a live topic can skip one
// message and go on.
// Implementation-only (not installed, *_detail.h): names ROS types.
#include <array>
#include <cstdint>
#include <string>

#include "core/dataset_types.h"
#include "core/image.h"
#include "ros/pressure_depth.h"
#include "ros/ros_messages_detail.h"

namespace pensight {

int64_t to_ns(const ros::Time& t);

// The camera of a sensor_msgs/CameraInfo, at the body origin looking forward (the usual mount
// where no cam0/sensor.yaml says otherwise). Throws pensight::Error naming `topic` and `fix` (how
// to give the calibration instead) for a size outside 1-16384 px, a K that is not a pinhole
// matrix, binning or a region of interest, or a distortion other than plumb_bob without k3.
CameraCalibration camera_from_info(const msg::CameraInfo& info, const std::string& topic,
                                   const std::string& fix);

// The DVL where no dvl0/sensor.yaml says: at the body origin looking forward, Janus beams 25 deg
// off its axis.
DvlCalibration default_dvl_calibration(double rate_hz);

// A geometry_msgs/TwistWithCovarianceStamped's body-frame (FRD) velocity over the net; a NaN
// component means no lock (valid false). Beam ranges stay NaN (beam_ranges_from pairs them).
DvlSample dvl_sample_from_twist(const msg::TwistWithCovarianceStamped& m);

// The 4 beam ranges [m] of a std_msgs/Float64MultiArray (a range that is not finite or not > 0
// is "no return", NaN). `problem` is set for another number of values.
std::array<double, 4> beam_ranges_from(const msg::Float64MultiArray& m, std::string& problem);

// Depth below the surface from a sensor_msgs/FluidPressure; `problem` set for a non-finite value.
PressureSample pressure_sample_from(const msg::FluidPressure& m, const WaterColumn& water,
                                    std::string& problem);

// Roll, pitch, yaw in P of a sensor_msgs/Imu orientation (REP 103, ros_frames.h); `problem` set
// when the message has no orientation (covariance[0] = -1) or it is not a unit quaternion.
AttitudeSample attitude_sample_from(const msg::Imu& m, std::string& problem);

// The frame of a sensor_msgs/Image or CompressedImage as 8-bit grey (image_decoding.h); throws
// pensight::Error as grey_from_raw_image / grey_from_compressed_image.
ImageU8 grey_from(const msg::Image& m, const std::string& topic);
ImageU8 grey_from(const msg::CompressedImage& m, int width_px, int height_px,
                  const std::string& topic);

}  // namespace pensight
