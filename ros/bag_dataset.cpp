#include "ros/bag_dataset.h"

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>

#include "core/error.h"
#include "core/log.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/dataset_writer.h"
#include "ros/bag_structure.h"
#include "ros/message_conversions_detail.h"
#include "ros/ros_messages_detail.h"

namespace pensight {
namespace fs = std::filesystem;
namespace {

struct TopicInfo {
  std::string type;
  size_t messages = 0;
};
using BagIndex = std::map<std::string, TopicInfo>;

void open_bag(rosbag::Bag& bag, const fs::path& file) {
  if (!fs::exists(file)) throw Error("bag '" + file.string() + "' not found");
  if (!fs::is_regular_file(file)) throw Error("bag '" + file.string() + "' is not a file");
  check_bag_structure(file);
  try {
    bag.open(file.string(), rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    throw Error("bag '" + file.string() + "' has no index (its recording was interrupted): run " +
                "`rosbag reindex " + file.string() + "` first");
  } catch (const rosbag::BagException& e) {
    throw Error("cannot read '" + file.string() + "' as a ROS 1 bag (" + e.what() +
                "): damaged, cut short (`rosbag reindex` repairs an interrupted recording) or "
                "another format; pensight reads ROS 1 .bag files (format 2.0), not ROS 2 bags");
  }
}

BagIndex index_bag(rosbag::Bag& bag, const fs::path& file) {
  BagIndex index;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    TopicInfo& t = index[c->topic];
    if (!t.type.empty() && t.type != c->datatype) {
      throw Error("bag '" + file.string() + "': topic '" + c->topic + "' carries both " + t.type +
                  " and " + c->datatype + "; pensight reads one type per topic");
    }
    t.type = c->datatype;
  }
  for (auto& [topic, info] : index)
    info.messages = rosbag::View(bag, rosbag::TopicQuery(topic)).size();
  return index;
}

std::string list_topics(const BagIndex& index) {
  std::string out;
  for (const auto& [topic, info] : index) {
    out += (out.empty() ? "" : ", ") + topic + " (" + info.type + ", " +
           std::to_string(info.messages) + " messages)";
  }
  return out;
}

// Whether the bag has messages on the role's topic; throws when they are of another type.
template <class Message>
bool has_topic(const BagIndex& index, const char* role, const std::string& topic) {
  const auto it = index.find(topic);
  if (it == index.end() || it->second.messages == 0) return false;
  const std::string want = msg::type_name<Message>();
  if (it->second.type != want) {
    throw Error("topic '" + topic + "' is " + it->second.type + " but the role '" + role +
                "' reads " + want + ": map '" + role + "' to a " + want +
                " topic with --topics TOPICS.yaml");
  }
  return true;
}

// Calls f(message, bag time) for each message on `topic`, in bag time order.
template <class Message, class F>
void for_each_message(rosbag::Bag& bag, const std::string& topic, F&& f) {
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic))) {
    const boost::shared_ptr<Message> message = [&] {
      const msg::MessageBytesLimit limit(m.size());
      return m.instantiate<Message>();
    }();
    if (!message) {
      throw Error("topic '" + topic + "': its " + m.getDataType() + " messages have MD5 sum " +
                  m.getMD5Sum() + ", not " + ros::message_traits::MD5Sum<Message>::value() +
                  ": the bag was recorded with another definition of the type");
    }
    f(*message, m.getTime());
  }
}

// Messages per second on `topic` from the bag times, to 0.01 Hz; `fallback` below 2 messages.
double rate_hz(rosbag::Bag& bag, const std::string& topic, double fallback) {
  size_t n = 0;
  int64_t first_ns = 0, last_ns = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic))) {
    last_ns = to_ns(m.getTime());
    if (n++ == 0) first_ns = last_ns;
  }
  if (n < 2 || last_ns <= first_ns) return fallback;
  return std::round(100.0 * static_cast<double>(n - 1) / seconds_between(first_ns, last_ns)) / 100;
}

// The messages of one sensor topic with the dataset reader's rule for sensor logs
// (read_dataset): bad ones are skipped and counted, too many bad ones fail the topic.
class SensorLog {
 public:
  explicit SensorLog(std::string topic) : topic_(std::move(topic)) {}

  // Counts a message stamped stamp_ns; returns whether it is kept: not when `problem` names one,
  // nor when it is not after the last kept message.
  bool keep(int64_t stamp_ns, const std::string& problem = {}) {
    ++messages_;
    const std::string why = !problem.empty()       ? problem
                            : stamp_ns <= last_ns_ ? "stamp repeats or goes back in time"
                                                   : "";
    if (why.empty()) {
      last_ns_ = stamp_ns;
      return true;
    }
    if (bad_.size() < kWarningsPerTopic) {
      bad_.push_back("topic '" + topic_ + "': message " + std::to_string(messages_) + " (stamp " +
                     std::to_string(stamp_ns) + " ns): " + why);
    }
    ++bad_count_;
    return false;
  }

  // Warns about the skipped messages; throws when more than kMaxSkippedRowFraction were bad.
  void finish(std::vector<SkippedMessages>& skipped) const {
    if (bad_count_ == 0) return;
    const std::string counted =
        std::to_string(bad_count_) + " of " + std::to_string(messages_) + " messages";
    if (static_cast<double>(bad_count_) > kMaxSkippedRowFraction * static_cast<double>(messages_)) {
      throw Error(bad_.front() + " (" + counted +
                  " are bad: check the topic's type, stamps and the --topics mapping)");
    }
    for (const std::string& b : bad_) log_warning(b + "; skipped");
    log_warning("topic '" + topic_ + "': " + counted + " skipped");
    skipped.push_back({topic_, bad_count_, messages_});
  }

 private:
  static constexpr size_t kWarningsPerTopic = 5;
  std::string topic_;
  size_t messages_ = 0, bad_count_ = 0;
  int64_t last_ns_ = INT64_MIN;
  std::vector<std::string> bad_;  // the first kWarningsPerTopic
};

CameraCalibration camera_calibration(rosbag::Bag& bag, const BagIndex& index,
                                     const BagConversionOptions& o,
                                     const std::string& image_topic) {
  if (!o.camera_file.empty()) return read_camera_yaml(o.camera_file);
  const std::string& topic = o.topics.camera_info;
  if (!has_topic<msg::CameraInfo>(index, "camera_info", topic)) {
    throw Error("no calibration for the camera: the bag has no " +
                msg::type_name<msg::CameraInfo>() + " messages on '" + topic +
                "'; give cam0/sensor.yaml with --camera, or map camera_info to the bag's topic "
                "with --topics TOPICS.yaml");
  }
  std::optional<CameraCalibration> calib;
  for_each_message<msg::CameraInfo>(bag, topic, [&](const msg::CameraInfo& info, ros::Time) {
    if (!calib) {
      calib =
          camera_from_info(info, topic, "give the camera's cam0/sensor.yaml with --camera instead");
    }
  });
  calib->rate_hz = rate_hz(bag, image_topic, calib->rate_hz);
  log_info(
      "note: no --camera: the camera is taken to sit at the body origin looking forward "
      "(optical axis along body x); give its cam0/sensor.yaml with --camera for its mount");
  return *calib;
}

DvlCalibration dvl_calibration(rosbag::Bag& bag, const BagConversionOptions& o) {
  if (!o.dvl_file.empty()) return read_dvl_yaml(o.dvl_file);
  const double rate = rate_hz(bag, o.topics.dvl_twist, 4.0);
  log_info(
      "note: no --dvl-sensor: the DVL is taken to sit at the body origin looking forward "
      "with Janus beams 25 deg off its axis; give its dvl0/sensor.yaml with --dvl-sensor");
  return default_dvl_calibration(rate);
}

void check_frame(const ImageU8& image, const PinholeCamera& cam, const std::string& topic) {
  check_image_size(image.width, image.height, cam, "topic '" + topic + "'", "image",
                   " (camera_info or --camera): give the calibration of this camera");
}

// The camera stream is strict (docs/reliability.md): every frame is kept, in time order.
size_t write_frames(rosbag::Bag& bag, const std::string& topic, bool compressed,
                    const PinholeCamera& cam, DatasetWriter& writer) {
  int64_t last_ns = INT64_MIN;
  size_t frames = 0;
  const auto add = [&](int64_t stamp_ns, const ImageU8& image) {
    if (stamp_ns <= last_ns) {
      throw Error("topic '" + topic + "': frame " + std::to_string(frames + 1) + " is stamped " +
                  std::to_string(stamp_ns) + " ns, not after the frame before it (" +
                  std::to_string(last_ns) + " ns): camera frames must be in time order in the bag");
    }
    check_frame(image, cam, topic);
    writer.add_frame(stamp_ns, image);
    last_ns = stamp_ns;
    ++frames;
  };
  if (compressed) {
    for_each_message<msg::CompressedImage>(
        bag, topic, [&](const msg::CompressedImage& m, ros::Time) {
          add(to_ns(m.header.stamp), grey_from(m, cam.width_px, cam.height_px, topic));
        });
  } else {
    for_each_message<msg::Image>(bag, topic, [&](const msg::Image& m, ros::Time) {
      add(to_ns(m.header.stamp), grey_from(m, topic));
    });
  }
  return frames;
}

struct RangesSample {
  int64_t bag_time_ns = 0;
  std::array<double, 4> range_m{};
};

std::vector<RangesSample> read_ranges(rosbag::Bag& bag, const std::string& topic,
                                      std::vector<SkippedMessages>& skipped) {
  SensorLog log(topic);
  std::vector<RangesSample> out;
  for_each_message<msg::Float64MultiArray>(
      bag, topic, [&](const msg::Float64MultiArray& m, ros::Time t) {
        std::string problem;
        const std::array<double, 4> range_m = beam_ranges_from(m, problem);
        if (log.keep(to_ns(t), problem)) out.push_back({to_ns(t), range_m});
      });
  log.finish(skipped);
  return out;
}

// The ranges nearest to stamp_ns within kDvlRangesMatchWindow_ns; NaN (not recorded) otherwise.
std::array<double, 4> nearest_ranges(const std::vector<RangesSample>& ranges, int64_t stamp_ns) {
  const auto after =
      std::lower_bound(ranges.begin(), ranges.end(), stamp_ns,
                       [](const RangesSample& r, int64_t t) { return r.bag_time_ns < t; });
  const RangesSample* best = nullptr;
  int64_t best_gap = kDvlRangesMatchWindow_ns;
  if (after != ranges.end() && after->bag_time_ns - stamp_ns <= best_gap) {
    best = &*after, best_gap = after->bag_time_ns - stamp_ns;
  }
  if (after != ranges.begin() && stamp_ns - std::prev(after)->bag_time_ns <= best_gap) {
    best = &*std::prev(after);
  }
  return best ? best->range_m : std::array<double, 4>{kNaN, kNaN, kNaN, kNaN};
}

size_t write_dvl(rosbag::Bag& bag, const BagTopics& topics, bool with_ranges, DatasetWriter& writer,
                 std::vector<SkippedMessages>& skipped) {
  const std::vector<RangesSample> ranges =
      with_ranges ? read_ranges(bag, topics.dvl_ranges, skipped) : std::vector<RangesSample>{};
  SensorLog log(topics.dvl_twist);
  size_t written = 0;
  for_each_message<msg::TwistWithCovarianceStamped>(
      bag, topics.dvl_twist, [&](const msg::TwistWithCovarianceStamped& m, ros::Time) {
        DvlSample s = dvl_sample_from_twist(m);
        if (!log.keep(s.timestamp_ns)) return;
        if (with_ranges) s.beam_range_m = nearest_ranges(ranges, s.timestamp_ns);
        writer.add_dvl(s);
        ++written;
      });
  log.finish(skipped);
  return written;
}

size_t write_pressure(rosbag::Bag& bag, const std::string& topic, const WaterColumn& water,
                      DatasetWriter& writer, std::vector<SkippedMessages>& skipped) {
  SensorLog log(topic);
  size_t written = 0;
  for_each_message<msg::FluidPressure>(bag, topic, [&](const msg::FluidPressure& m, ros::Time) {
    std::string problem;
    const PressureSample s = pressure_sample_from(m, water, problem);
    if (!log.keep(s.timestamp_ns, problem)) return;
    writer.add_pressure(s);
    ++written;
  });
  log.finish(skipped);
  return written;
}

size_t write_attitude(rosbag::Bag& bag, const std::string& topic, DatasetWriter& writer,
                      std::vector<SkippedMessages>& skipped) {
  SensorLog log(topic);
  size_t written = 0;
  for_each_message<msg::Imu>(bag, topic, [&](const msg::Imu& m, ros::Time) {
    std::string problem;
    const AttitudeSample s = attitude_sample_from(m, problem);
    if (!log.keep(s.timestamp_ns, problem)) return;
    writer.add_attitude(s);
    ++written;
  });
  log.finish(skipped);
  return written;
}

void check_options(const BagConversionOptions& o) {
  if (o.scene_file.empty()) {
    throw Error(
        "a bag does not know the net: give its scene.yaml (net_mesh_size_m, "
        "pen_radius_m; dataset-format.md) with --scene");
  }
  if (!(o.water.density_kg_m3 > 0) || !std::isfinite(o.water.density_kg_m3)) {
    throw Error(
        "water density (--water-density) must be > 0 kg/m^3 (sea water ~1025, fresh "
        "~1000)");
  }
  if (!(o.water.surface_pressure_pa >= 0) || !std::isfinite(o.water.surface_pressure_pa)) {
    throw Error("surface pressure (--surface-pressure) must be >= 0 Pa (the atmosphere: 101325)");
  }
}

BagConversionSummary convert(rosbag::Bag& bag, const fs::path& bag_file, const fs::path& out,
                             const BagConversionOptions& o) {
  const SceneConfig scene = read_scene_yaml(o.scene_file);
  const BagIndex index = index_bag(bag, bag_file);
  if (index.empty()) throw Error("bag '" + bag_file.string() + "' holds no messages");
  const BagTopics& t = o.topics;
  BagConversionSummary summary;
  const bool raw = has_topic<msg::Image>(index, "image", t.image);
  if (!raw && !has_topic<msg::CompressedImage>(index, "image_compressed", t.image_compressed)) {
    throw Error("bag '" + bag_file.string() + "' has no camera images on '" + t.image + "' (" +
                msg::type_name<msg::Image>() + ") or '" + t.image_compressed + "' (" +
                msg::type_name<msg::CompressedImage>() + "); its topics: " + list_topics(index) +
                "; map image or image_compressed to the camera's topic with --topics TOPICS.yaml");
  }
  summary.image_topic = raw ? t.image : t.image_compressed;

  DatasetContents contents;
  contents.scene = scene;
  contents.cam0 = camera_calibration(bag, index, o, summary.image_topic);
  const bool dvl = has_topic<msg::TwistWithCovarianceStamped>(index, "dvl_twist", t.dvl_twist);
  if (dvl) contents.dvl0 = dvl_calibration(bag, o);
  contents.dvl_beam_ranges =
      dvl && has_topic<msg::Float64MultiArray>(index, "dvl_ranges", t.dvl_ranges);
  contents.pressure0 = has_topic<msg::FluidPressure>(index, "pressure", t.pressure);
  contents.imu0 = has_topic<msg::Imu>(index, "imu", t.imu);
  contents.groundtruth0 = false;
  if (!o.dvl_file.empty() && !dvl) {
    log_warning("--dvl-sensor is not used: the bag has no DVL twists on '" + t.dvl_twist + "'");
  }

  DatasetWriter writer(out, contents);
  summary.frames = write_frames(bag, summary.image_topic, !raw, contents.cam0.camera, writer);
  if (dvl) {
    summary.dvl_samples = write_dvl(bag, t, contents.dvl_beam_ranges, writer, summary.skipped);
  }
  if (contents.pressure0) {
    summary.pressure_samples = write_pressure(bag, t.pressure, o.water, writer, summary.skipped);
  }
  if (contents.imu0) summary.attitude_samples = write_attitude(bag, t.imu, writer, summary.skipped);
  writer.finish();
  return summary;
}

}  // namespace

BagConversionSummary bag_to_dataset(const fs::path& bag_file, const fs::path& out,
                                    const BagConversionOptions& options) {
  check_options(options);
  rosbag::Bag bag;
  open_bag(bag, bag_file);
  try {
    return convert(bag, bag_file, out, options);
  } catch (const ros::Exception& e) {  // rosbag's and the message deserializer's
    throw Error("bag '" + bag_file.string() + "' is damaged: " + e.what());
  }
}

}  // namespace pensight
