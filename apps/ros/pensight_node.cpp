// pensight_node: the pipeline (pipeline.h) as a ROS 1 node, a drop-in for the published FFT,
// TRUDepth, relative-pose, global-pose and wavemap nodes (docs/ros.md). Subscribes to the camera,
// its camera_info, the DVL, the pressure sensor and the IMU under the names of bag_topics.h (ROS
// remapping renames them); publishes the net points, relative and global pose, dense depth, the
// map and the tf pen -> base_link, stamped with the camera frame's time.
//
// Threads: every subscriber callback runs on one spinner thread, so the node's own state
// (the camera, the DVL pairing) needs no lock; the pipeline's delivery thread publishes (ROS
// publishers are thread-safe) and counts the latency under a mutex.
#include <ros/ros.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "apps/default_model.h"
#include "apps/ros/node_config.h"
#include "apps/ros/node_messages.h"
#include "core/error.h"
#include "core/units.h"
#include "pipeline/pipeline.h"
#include "ros/bag_topics.h"
#include "ros/message_conversions_detail.h"
#include "tools/runner.h"
#if PENSIGHT_HAS_MAPPING
#include "mapping/map_io.h"
#include "mapping/mapping_stage.h"
#endif

namespace pensight::node {
namespace {

using Clock = std::chrono::steady_clock;

// Samples kept while the camera is unknown (the pipeline starts with it): 60 s of a 20 Hz IMU,
// 10 Hz pressure and 4 Hz DVL.
constexpr size_t kMaxSamplesBeforeStart = 2048;
// Frames that wait for the camera's calibration (camera_info may arrive just after the first
// images); older ones are dropped and counted.
constexpr size_t kMaxFramesBeforeStart = 10;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

class PensightNode {
 public:
  PensightNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, NodeConfig config)
      : config_(std::move(config)), pnh_(pnh) {
    const BagTopics t;
    image_sub_ = nh.subscribe(t.image, 2, &PensightNode::on_image, this);
    compressed_sub_ = nh.subscribe(t.image_compressed, 2, &PensightNode::on_compressed, this);
    if (!config_.camera) {
      camera_info_sub_ = nh.subscribe(t.camera_info, 1, &PensightNode::on_camera_info, this);
    }
    if (config_.has_dvl) {
      twist_sub_ = nh.subscribe(t.dvl_twist, 20, &PensightNode::on_twist, this);
      ranges_sub_ = nh.subscribe(t.dvl_ranges, 20, &PensightNode::on_ranges, this);
    }
    if (config_.has_pressure) {
      pressure_sub_ = nh.subscribe(t.pressure, 50, &PensightNode::on_pressure, this);
    }
    if (config_.has_imu) imu_sub_ = nh.subscribe(t.imu, 100, &PensightNode::on_imu, this);

    net_points_pub_ = pnh.advertise<msg::PointCloud2>("net_points", 5);
    sparse_depth_pub_ = pnh.advertise<msg::PointCloud2>("sparse_depth", 5);
    net_distance_pub_ = pnh.advertise<msg::Float64>("net_distance", 10);
    net_pitch_pub_ = pnh.advertise<msg::Float64>("net_pitch", 10);
    net_yaw_pub_ = pnh.advertise<msg::Float64>("net_yaw", 10);
    relative_pose_pub_ = pnh.advertise<msg::PoseStamped>("relative_pose", 10);
    global_pose_pub_ = pnh.advertise<msg::PoseWithCovarianceStamped>("global_pose", 10);
    depth_pub_ = pnh.advertise<msg::Image>("depth", 2);
    tf_pub_ = nh.advertise<msg::TFMessage>("/tf", 20);
    tf_static_pub_ = nh.advertise<msg::TFMessage>("/tf_static", 1, /*latch=*/true);

    if (config_.camera) start(*config_.camera);
    camera_wait_timer_ =
        nh.createWallTimer(ros::WallDuration(config_.camera_info_timeout_s),
                           [this](const ros::WallTimerEvent&) { warn_if_no_camera(); });
  }

  // Drains the pipeline (every pushed frame is published) and logs the run's figures.
  void finish() {
    flush_twist();
    if (pipeline_) pipeline_->finish();
#if PENSIGHT_HAS_MAPPING
    if (mapper_) mapper_->finish();
#endif
    std::lock_guard lock(latency_mutex_);
    std::vector<double> sorted = latency_ms_;
    std::sort(sorted.begin(), sorted.end());
    const auto at = [&](double q) {
      return sorted.empty()
                 ? kNaN
                 : sorted[static_cast<size_t>(q * static_cast<double>(sorted.size() - 1))];
    };
    const double wall_s = std::chrono::duration<double>(last_.wall - first_.wall).count();
    ROS_INFO(
        "pensight_node: %zu frames published (%zu dropped before the camera was known, %zu "
        "refused); latency from receiving the image to publishing ~relative_pose: median %.1f "
        "ms, p95 %.1f ms, max %.1f ms; CPU %.0f %% of one core from the first frame to the last "
        "(%.1f s)",
        latency_ms_.size(), dropped_before_camera_, refused_frames_, at(0.5), at(0.95), at(1.0),
        100 * (last_.cpu_s - first_.cpu_s) / std::max(wall_s, 1e-9), wall_s);
    if (pipeline_) {
      ROS_INFO("%s", global_pose::describe(pipeline_->global_pose_counters()).c_str());
    }
  }

 private:
  static double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }

  void start(const CameraCalibration& cam0) {
    cam0_ = cam0;
    PipelineConfig pc;
    pc.camera = cam0.camera;
    pc.detector = detector_config(config_.scene, config_.detector);
    pc.global_pose = global_pose_config(config_.scene, cam0,
                                        config_.has_dvl ? std::optional(config_.dvl) : std::nullopt,
                                        config_.has_pressure, config_.has_imu);
    const std::filesystem::path model =
        config_.model == "auto"   ? app::find_default_depth_model(cam0.camera)
        : config_.model == "none" ? std::filesystem::path()
                                  : std::filesystem::path(config_.model);
    if (!model.empty()) {
      pc.depth = DepthEstimatorConfig{.model = model,
                                      .backend = config_.depth_backend,
                                      .cpu_inference = config_.depth_cpu_inference,
                                      .cpu_threads = config_.detector.cpu_threads,
                                      .net_curvature_per_m = net_curvature_per_m(config_.scene)};
    }
    tf_static_pub_.publish(
        base_link_to_camera(cam0.T_body_camera, 0, config_.base_frame, config_.camera_frame));
    pc.sensor_wait_ms = 1000 * config_.sensor_wait_s;
    pc.on_frame = [this](const FrameResult& r) { publish(r); };
    pipeline_ = std::make_unique<Pipeline>(pc, device_);
    ROS_INFO("pensight_node: %dx%d camera, fx %.1f px; net detection on %s; dense depth %s",
             cam0.camera.width_px, cam0.camera.height_px, cam0.camera.fx_px,
             pipeline_->backend_description().c_str(),
             model.empty() ? "off (~model)" : pipeline_->depth_description().c_str());
#if PENSIGHT_HAS_MAPPING
    if (pc.depth && config_.map_rate_hz > 0) {
      map_pub_ = pnh_.advertise<msg::PointCloud2>("map", 1);
      mapper_ = std::make_unique<mapping::MappingStage>(cam0.camera, mapping::MapConfig{});
      map_timer_ = pnh_.createWallTimer(ros::WallDuration(1 / config_.map_rate_hz),
                                        [this](const ros::WallTimerEvent&) { publish_map(); });
    }
#endif
    for (const auto& push_to : samples_before_start_) push_to(*pipeline_);
    samples_before_start_.clear();
    for (const auto& frame : frames_before_start_) frame();
    frames_before_start_.clear();
  }

  // DvlSample, PressureSample or AttitudeSample.
  template <class Sample>
  void push(const Sample& s) {
    if (pipeline_) {
      pipeline_->push(s);
    } else if (samples_before_start_.size() < kMaxSamplesBeforeStart) {
      samples_before_start_.push_back([s](Pipeline& p) { p.push(s); });
    }
  }

  void warn_if_no_camera() {
    if (pipeline_) return;
    ROS_ERROR(
        "pensight_node: no sensor_msgs/CameraInfo on '%s' yet (%zu images wait for it, %zu "
        "dropped): publish "
        "the camera's calibration there, remap it (%s:=YOUR_TOPIC), or set ~camera_yaml to its "
        "cam0/sensor.yaml",
        camera_info_sub_.getTopic().c_str(), frames_before_start_.size(), dropped_before_camera_,
        BagTopics{}.camera_info.c_str());
  }

  void on_camera_info(const boost::shared_ptr<const pensight::msg::CameraInfo>& m) {
    if (pipeline_) return;
    try {
      start(camera_from_info(*m, camera_info_sub_.getTopic(),
                             "publish a pinhole calibration or set ~camera_yaml"));
    } catch (const Error& e) {
      ROS_ERROR_THROTTLE(5, "pensight_node: %s", e.what());
    }
  }

  void on_image(const boost::shared_ptr<const pensight::msg::Image>& m) {
    if (wait_for_camera([this, m] { on_image(m); })) return;
    on_frame(to_ns(m->header.stamp), image_sub_.getTopic(),
             [&] { return grey_from(*m, image_sub_.getTopic()); });
  }

  void on_compressed(const boost::shared_ptr<const pensight::msg::CompressedImage>& m) {
    if (wait_for_camera([this, m] { on_compressed(m); })) return;
    on_frame(to_ns(m->header.stamp), compressed_sub_.getTopic(), [&] {
      return grey_from(*m, cam0_->camera.width_px, cam0_->camera.height_px,
                       compressed_sub_.getTopic());
    });
  }

  // Before the camera is known, keeps the frame (its callback again) for start(); true then.
  bool wait_for_camera(std::function<void()> frame) {
    if (pipeline_) return false;
    frames_before_start_.push_back(std::move(frame));
    if (frames_before_start_.size() > kMaxFramesBeforeStart) {
      frames_before_start_.pop_front();
      ++dropped_before_camera_;
    }
    return true;
  }

  template <class Decode>
  void on_frame(int64_t stamp_ns, const std::string& topic, Decode&& decode) {
    const Clock::time_point received = Clock::now();
    flush_twist();  // a DVL sample before the frame reaches the estimator before it
    ranges_.reset();
    try {
      if (stamp_ns <= last_frame_ns_) {
        throw Error("topic '" + topic + "': frame stamped " + std::to_string(stamp_ns) +
                    " ns is not after the one before (" + std::to_string(last_frame_ns_) +
                    " ns); frames are taken in time order (a bag played in a loop restarts its "
                    "time: restart the node)");
      }
      CameraFrame frame{stamp_ns, decode(), nullptr};
      check_image_size(frame.image.width, frame.image.height, cam0_->camera,
                       "topic '" + topic + "'", "image",
                       " (camera_info or ~camera_yaml): give this camera's calibration");
      {
        std::lock_guard lock(latency_mutex_);
        received_[stamp_ns] = received;
      }
      if (last_frame_ns_ == INT64_MIN) {
        std::lock_guard lock(latency_mutex_);
        first_ = {Clock::now(), cpu_seconds()};
      }
      last_frame_ns_ = stamp_ns;
      pipeline_->push(std::move(frame));
    } catch (const Error& e) {
      ++refused_frames_;
      log_refusal(e.what());
    }
  }

  // A new kind of refused frame is logged at once, a repeat of the last kind at most every 5 s
  // (a live camera at 10 Hz would flood the log). The kind is the message without its digits
  // (stamps, sizes).
  void log_refusal(const std::string& what) {
    std::string kind = what;
    std::erase_if(kind, [](char c) { return c >= '0' && c <= '9'; });
    const Clock::time_point now = Clock::now();
    if (kind == last_refusal_kind_ && now - last_refusal_log_ < std::chrono::seconds(5)) return;
    last_refusal_kind_ = std::move(kind);
    last_refusal_log_ = now;
    ROS_ERROR("pensight_node: %s; frame skipped (%zu so far)", what.c_str(), refused_frames_);
  }

  // The DVL's twist and its beam ranges (a separate message without a header) pair by arrival
  // order, not by a clock that a busy node would misread: while the ranges topic has a publisher
  // a twist is held until its ranges arrive, or the next twist or frame; ranges that arrive first
  // wait for the next twist, until a frame or other ranges arrive.
  void on_twist(const boost::shared_ptr<const pensight::msg::TwistWithCovarianceStamped>& m) {
    flush_twist();
    DvlSample s = dvl_sample_from_twist(*m);
    if (ranges_) {
      s.beam_range_m = *ranges_;
      ranges_.reset();
      push(s);
    } else if (ranges_sub_.getNumPublishers() > 0) {
      pending_twist_ = s;
    } else {
      push(s);
    }
  }

  void on_ranges(const boost::shared_ptr<const pensight::msg::Float64MultiArray>& m) {
    std::string problem;
    const std::array<double, 4> range_m = beam_ranges_from(*m, problem);
    if (!problem.empty()) {
      ROS_WARN_THROTTLE(5, "pensight_node: topic '%s': %s; skipped", ranges_sub_.getTopic().c_str(),
                        problem.c_str());
      return;
    }
    if (pending_twist_) {
      pending_twist_->beam_range_m = range_m;
      push(*pending_twist_);
      pending_twist_.reset();
    } else {
      ranges_ = range_m;
    }
  }

  void flush_twist() {
    if (!pending_twist_) return;
    push(*pending_twist_);
    pending_twist_.reset();
  }

  void on_pressure(const boost::shared_ptr<const pensight::msg::FluidPressure>& m) {
    std::string problem;
    const PressureSample s = pressure_sample_from(*m, config_.water, problem);
    if (problem.empty()) return push(s);
    ROS_WARN_THROTTLE(5, "pensight_node: topic '%s': %s; skipped", pressure_sub_.getTopic().c_str(),
                      problem.c_str());
  }

  void on_imu(const boost::shared_ptr<const pensight::msg::Imu>& m) {
    std::string problem;
    const AttitudeSample s = attitude_sample_from(*m, problem);
    if (problem.empty()) return push(s);
    ROS_WARN_THROTTLE(5, "pensight_node: topic '%s': %s; skipped", imu_sub_.getTopic().c_str(),
                      problem.c_str());
  }

  // On the pipeline's delivery thread.
  void publish(const FrameResult& r) {
    if (!r.error.empty()) ROS_WARN_THROTTLE(5, "pensight_node: frame: %s", r.error.c_str());
    const msg::Header camera = header(r.timestamp_ns, config_.camera_frame);
    const FftRelativePose& pose = r.detection.pose;
    net_points_pub_.publish(net_points_cloud(r.detection, camera));
    sparse_depth_pub_.publish(sparse_depth_cloud(r.detection, cam0_->camera, camera));
    msg::Float64 value;
    value.data = pose.d_net_m;
    net_distance_pub_.publish(value);
    value.data = pose.pitch_net_rad;
    net_pitch_pub_.publish(value);
    value.data = pose.psi_net_rad;
    net_yaw_pub_.publish(value);
    relative_pose_pub_.publish(relative_pose(pose, camera));
    {
      std::lock_guard lock(latency_mutex_);
      const auto it = received_.find(r.timestamp_ns);
      if (it != received_.end()) {
        latency_ms_.push_back(ms_since(it->second));
        received_.erase(received_.begin(), std::next(it));
        last_ = {Clock::now(), cpu_seconds()};
      }
    }
    if (r.dense_depth_m) depth_pub_.publish(depth_image(*r.dense_depth_m, camera));
    global_pose_pub_.publish(global_pose(r.global_pose, header(r.timestamp_ns, config_.pen_frame)));
    const msg::TFMessage tf =
        pen_to_base_link(r.global_pose, r.timestamp_ns, config_.pen_frame, config_.base_frame);
    if (!tf.transforms.empty()) tf_pub_.publish(tf);
#if PENSIGHT_HAS_MAPPING
    if (mapper_) mapper_->push(r);
#endif
  }

#if PENSIGHT_HAS_MAPPING
  void publish_map() {
    if (map_pub_.getNumSubscribers() == 0) return;
    std::vector<Eigen::Vector3f> centres;
    mapper_->read(
        [&](const mapping::OccupancyMap& map) { centres = mapping::occupied_voxel_centres(map); });
    map_pub_.publish(map_cloud(centres, header(last_frame_ns_, config_.pen_frame)));
  }
#endif

  NodeConfig config_;
  ros::NodeHandle& pnh_;
  Device device_;
  std::optional<CameraCalibration> cam0_;
  std::unique_ptr<Pipeline> pipeline_;
  std::vector<std::function<void(Pipeline&)>> samples_before_start_;
  std::deque<std::function<void()>> frames_before_start_;
  int64_t last_frame_ns_ = INT64_MIN;
  size_t dropped_before_camera_ = 0, refused_frames_ = 0;
  std::string last_refusal_kind_;
  Clock::time_point last_refusal_log_;
  std::optional<DvlSample> pending_twist_;
  std::optional<std::array<double, 4>> ranges_;

  std::mutex latency_mutex_;
  std::map<int64_t, Clock::time_point> received_;  // frame stamp -> when its image arrived
  std::vector<double> latency_ms_;
  struct Instant {
    Clock::time_point wall;
    double cpu_s = 0;  // the process's CPU time (all threads)
  };
  Instant first_, last_;  // the first frame received, the last relative pose published

  ros::Subscriber image_sub_, compressed_sub_, camera_info_sub_, twist_sub_, ranges_sub_,
      pressure_sub_, imu_sub_;
  ros::Publisher net_points_pub_, sparse_depth_pub_, net_distance_pub_, net_pitch_pub_,
      net_yaw_pub_, relative_pose_pub_, global_pose_pub_, depth_pub_, tf_pub_, tf_static_pub_,
      map_pub_;
  ros::WallTimer camera_wait_timer_, map_timer_;
#if PENSIGHT_HAS_MAPPING
  std::unique_ptr<mapping::MappingStage> mapper_;
#endif
};

}  // namespace
}  // namespace pensight::node

namespace {

std::atomic<bool> g_stop{false};

// SIGINT and SIGTERM end the spin, not ROS: the pipeline's last frames are still published and
// the summary logged before ROS shuts down (ros::shutdown also ends rosconsole).
void request_stop(int) {
  g_stop = true;
}

}  // namespace

int main(int argc, char** argv) {
  // `pensight_node --params`: the table of docs/ros.md's generated section, without ROS.
  if (argc == 2 && std::string_view(argv[1]) == "--params") {
    std::fputs(pensight::node::node_params_markdown().c_str(), stdout);
    return 0;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each log line as it comes, also into a file
  ros::init(argc, argv, "pensight_node", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  ros::NodeHandle nh, pnh("~");
  int rc = 0;
  try {
    pensight::node::PensightNode node(nh, pnh, pensight::node::read_node_config(pnh));
    // One callback thread: the node's state is only touched there.
    ros::AsyncSpinner spinner(1);
    spinner.start();
    while (!g_stop && ros::ok()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    spinner.stop();
    node.finish();
  } catch (const std::exception& e) {
    ROS_FATAL("pensight_node: %s", e.what());
    rc = 2;
  }
  ros::shutdown();
  return rc;
}
