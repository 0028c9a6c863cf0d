// pensight_node with a real roscore (Debian's ros-core): a rendered sequence written as a bag and
// played with `rosbag play` into the node; the node must publish every topic once per camera frame
// at the camera's rate, with the estimates `pensight run` gives for the same bag; and it must say
// what is wrong, without crashing, when camera_info is missing, an image has an unsupported
// encoding or a parameter is bad.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <ros/ros.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

#include "apps/ros/node_messages.h"
#include "pipeline/dataset/estimates_csv.h"
#include "ros/bag_dataset.h"
#include "tests/ros/dataset_to_bag.h"
#include "tests/support/child_process.h"
#include "tests/support/rendered_run.h"
#include "tests/support/test_seed.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/runner.h"

namespace pensight {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using testing::ChildProcess;

// A TCP port nobody listens on now (the kernel's choice for port 0).
int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

// `rosbag play`'s rate: PENSIGHT_ROS_PLAY_RATE (the sanitizer run's node is slower than the
// camera, and frames it cannot take in time are dropped in the subscriber's queue, as live), else
// real time.
double play_rate() {
  const char* rate = std::getenv("PENSIGHT_ROS_PLAY_RATE");
  return rate ? std::atof(rate) : 1.0;
}

// Playback starts once every topic of the bag has a subscriber: what a publisher sends before a
// subscriber's connection is up is lost, and on a loaded machine rosbag's default 0.2 s wait after
// advertising is not always enough.
ChildProcess play_bag(const fs::path& bag, const fs::path& log) {
  return ChildProcess({"rosbag", "play", "--quiet", "--wait-for-subscribers", "-r",
                       std::to_string(play_rate()), bag.string()},
                      log);
}

template <class Condition>
bool wait_for(Condition&& done, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

// Messages of one topic as they arrive, with their arrival time.
template <class Message>
class Recorder {
 public:
  Recorder(ros::NodeHandle& nh, const std::string& topic)
      : sub_(nh.subscribe(topic, 1000, &Recorder::on_message, this)) {}
  std::vector<Message> messages() const {
    std::lock_guard lock(mutex_);
    return messages_;
  }
  std::vector<double> arrivals_s() const {
    std::lock_guard lock(mutex_);
    return arrivals_s_;
  }
  size_t size() const {
    std::lock_guard lock(mutex_);
    return messages_.size();
  }
  // Connected to a publisher (roscpp sets up subscriptions asynchronously: what a publisher
  // sends before is not delivered).
  bool connected() const { return sub_.getNumPublishers() > 0; }

 private:
  void on_message(const boost::shared_ptr<const Message>& m) {
    std::lock_guard lock(mutex_);
    messages_.push_back(*m);
    arrivals_s_.push_back(ros::WallTime::now().toSec());
  }
  ros::Subscriber sub_;
  mutable std::mutex mutex_;
  std::vector<Message> messages_;
  std::vector<double> arrivals_s_;
};

// Until every recorder is connected to its publisher (at most 30 s), then half a second more for
// the connections' handshakes.
template <class... Recorders>
bool connected(const Recorders&... recorders) {
  const bool all = wait_for([&] { return (recorders.connected() && ...); }, 30s);
  std::this_thread::sleep_for(500ms);
  return all;
}

class NodeTest : public ::testing::Test {
 protected:
  // One roscore on a free port and one rendered sequence (follow.yaml, 3 s, fresh sensor noise)
  // as a bag, for the suite.
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("pensight_node_test_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const std::string uri = "http://127.0.0.1:" + std::to_string(free_port());
    ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
    ::setenv("ROS_IP", "127.0.0.1", 1);  // a CI machine's host name may not resolve
    ::setenv("ROS_HOME", dir_->c_str(), 1);
    ::setenv("ROS_LOG_DIR", (*dir_ / "log").c_str(), 1);
    roscore_ =
        new ChildProcess({"roscore", "-p", uri.substr(uri.rfind(':') + 1)}, *dir_ / "roscore.log");
    int argc = 0;
    ros::init(argc, nullptr, "pensight_node_test", ros::init_options::NoSigintHandler);
    spinner_ = new ros::AsyncSpinner(1);
    spinner_->start();

    sim::Scenario s = testing::shipped_scenario("follow.yaml", 3.0);
    s.seed = testing::fresh_seed();
    sim::generate_dataset(s, *testing::test_renderer(s), *dir_ / "original");
    original_ = new Dataset(read_dataset(*dir_ / "original"));
    testing::dataset_to_bag(*original_, bag_file());
    if (!wait_for([] { return ros::master::check(); }, 30s)) {
      FAIL() << "roscore did not start on " << uri << ":\n" << roscore_->log();
    }
  }
  static void TearDownTestSuite() {
    spinner_->stop();
    delete spinner_;
    ros::shutdown();
    delete roscore_;
    delete original_;
    fs::remove_all(*dir_);
    delete dir_;
  }

  static const fs::path& dir() { return *dir_; }
  static fs::path bag_file() { return *dir_ / "follow.bag"; }
  static const Dataset& original() { return *original_; }

  // pensight_node with private parameters given as `_name:=value` arguments.
  static std::unique_ptr<ChildProcess> start_node(const std::string& name,
                                                  std::vector<std::string> params) {
    std::vector<std::string> argv = {PENSIGHT_NODE_BIN, "__name:=" + name};
    for (std::string& p : params) argv.push_back("_" + p);
    return std::make_unique<ChildProcess>(argv, dir() / (name + ".log"));
  }

  // The node's topics seen by the master (it advertises them once it runs).
  static bool advertised(const std::string& topic) {
    ros::master::V_TopicInfo topics;
    ros::master::getTopics(topics);
    for (const auto& t : topics)
      if (t.name == topic) return true;
    return false;
  }

  // `pensight run` on `bag` (as `pensight run BAG --scene SCENE`), its outputs in dir()/name:
  // the rows of its estimates.csv.
  static std::vector<EstimateRow> run_estimates(const fs::path& bag, const fs::path& scene,
                                                const std::string& name) {
    BagConversionOptions o;
    o.scene_file = scene;
    bag_to_dataset(bag, dir() / (name + "_dataset"), o);
    RunOptions options;
    options.detector.backend = Backend::kCpu;
    options.write_published_global_pose = false;
    run_dataset(read_dataset(dir() / (name + "_dataset")), dir() / name, options,
                testing::test_device());
    return read_estimates_csv(dir() / name / "estimates.csv");
  }

  static std::string scene_param() { return "scene:=" + (original().root / "scene.yaml").string(); }

 private:
  static fs::path* dir_;
  static ChildProcess* roscore_;
  static ros::AsyncSpinner* spinner_;
  static Dataset* original_;
};

fs::path* NodeTest::dir_ = nullptr;
ChildProcess* NodeTest::roscore_ = nullptr;
ros::AsyncSpinner* NodeTest::spinner_ = nullptr;
Dataset* NodeTest::original_ = nullptr;

void expect_same(double node, double run, const std::string& what) {
  if (std::isnan(run)) {
    EXPECT_TRUE(std::isnan(node)) << what << ": " << node << " where run has NaN";
  } else {
    // estimates.csv holds 9 significant digits.
    EXPECT_NEAR(node, run, 2e-8 * std::max(1.0, std::abs(run))) << what;
  }
}

TEST_F(NodeTest, PublishesEveryTopicPerFrameAtTheCameraRateWithTheEstimatesOfRun) {
  ros::NodeHandle nh;
  const std::string ns = "/pensight";
  Recorder<node::msg::PoseStamped> relative(nh, ns + "/relative_pose");
  Recorder<node::msg::Float64> distance(nh, ns + "/net_distance"), pitch(nh, ns + "/net_pitch"),
      yaw(nh, ns + "/net_yaw");
  Recorder<node::msg::PointCloud2> points(nh, ns + "/net_points"), sparse(nh, ns + "/sparse_depth");
  Recorder<node::msg::PoseWithCovarianceStamped> global(nh, ns + "/global_pose");
  Recorder<node::msg::TFMessage> tf(nh, "/tf");
  auto node = start_node("pensight", {scene_param(), "model:=none", "backend:=cpu"});
  ASSERT_TRUE(wait_for([] { return advertised("/pensight/relative_pose"); }, 30s)) << node->log();
  ASSERT_TRUE(connected(relative, distance, pitch, yaw, points, sparse, global, tf)) << node->log();

  ChildProcess play = play_bag(bag_file(), dir() / "play.log");
  ASSERT_EQ(play.wait(120s), 0) << play.log();
  const size_t frames = original().frames.size();
  wait_for([&] { return relative.size() >= frames && global.size() >= frames; }, 30s);
  ASSERT_EQ(node->stop(30s), 0) << node->log();
  const std::string log = node->log();
  const size_t summary = log.find(std::to_string(frames) + " frames published");
  ASSERT_NE(summary, std::string::npos) << log;
  std::printf("%s\n", log.substr(summary, log.find('\n', summary) - summary).c_str());

  ASSERT_EQ(relative.size(), frames);
  EXPECT_EQ(distance.size(), frames);
  EXPECT_EQ(pitch.size(), frames);
  EXPECT_EQ(yaw.size(), frames);
  EXPECT_EQ(points.size(), frames);
  EXPECT_EQ(sparse.size(), frames);
  ASSERT_EQ(global.size(), frames);
  EXPECT_GT(tf.size(), frames / 2);  // every frame with a global pose
  // The node keeps the camera's 10 Hz (at the play rate): the mean interval of the relative poses.
  const std::vector<double> t = relative.arrivals_s();
  EXPECT_NEAR((t.back() - t.front()) / static_cast<double>(frames - 1), 0.1 / play_rate(),
              0.02 / play_rate());

  const std::vector<EstimateRow> rows =
      run_estimates(bag_file(), original().root / "scene.yaml", "run");
  ASSERT_EQ(rows.size(), frames);

  const auto rel = relative.messages();
  const auto d = distance.messages(), p = pitch.messages(), y = yaw.messages();
  const auto g = global.messages();
  size_t with_global_pose = 0;
  for (size_t i = 0; i < frames; ++i) {
    const std::string at = "frame " + std::to_string(i);
    ASSERT_EQ(rel[i].header.stamp.toNSec(), static_cast<uint64_t>(rows[i].timestamp_ns)) << at;
    EXPECT_EQ(rel[i].header.frame_id, "camera");
    expect_same(rel[i].pose.position.z, rows[i].d_net_fft_m, at + " relative_pose z");
    expect_same(d[i].data, rows[i].d_net_fft_m, at + " net_distance");
    expect_same(p[i].data, rows[i].pitch_net_fft_rad, at + " net_pitch");
    expect_same(y[i].data, rows[i].psi_net_fft_rad, at + " net_yaw");
    ASSERT_EQ(g[i].header.stamp.toNSec(), static_cast<uint64_t>(rows[i].timestamp_ns)) << at;
    EXPECT_EQ(g[i].header.frame_id, "pen");
    const auto& q = g[i].pose.pose.orientation;
    const auto& pos = g[i].pose.pose.position;
    // base_link is FLU; the body (FRD) turns by the same yaw.
    const Eigen::Matrix3d R_pen_flu = Eigen::Quaterniond(q.w, q.x, q.y, q.z).toRotationMatrix();
    const Eigen::Matrix3d R_pen_body = R_pen_flu * Eigen::Vector3d(1, -1, -1).asDiagonal();
    expect_same(std::hypot(pos.x, pos.y), rows[i].r_g_m, at + " r_g");
    expect_same(std::isnan(rows[i].rho_g_rad) ? kNaN : std::atan2(pos.y, pos.x), rows[i].rho_g_rad,
                at + " rho_g");
    expect_same(pos.z, rows[i].z_g_m, at + " z_g");
    expect_same(std::isnan(rows[i].psi_g_rad) ? kNaN : rpy_from_rotation(R_pen_body).z(),
                rows[i].psi_g_rad, at + " psi_g");
    with_global_pose += std::isfinite(rows[i].psi_g_rad);
  }
  EXPECT_GT(with_global_pose, frames / 2);
}

// The real frame of ../shared/real (a full-scale pen, 1280x720, sheared square mesh), sent as a
// PNG CompressedImage: the node finds the net in it as `pensight run` does on the same bag.
TEST_F(NodeTest, FindsTheNetInTheRealFrameAsRunDoes) {
  const fs::path real = fs::path(PENSIGHT_SHARED_DIR) / "real" / "solaqua_close";
  const Dataset d = read_dataset(real);
  testing::BagWriteOptions w;
  w.image_encoding = "png";
  const fs::path bag = dir() / "real.bag";
  testing::dataset_to_bag(d, bag, w);
  ros::NodeHandle nh;
  Recorder<node::msg::Float64> distance(nh, "/real/net_distance"), yaw(nh, "/real/net_yaw");
  auto node = start_node(
      "real", {"scene:=" + (real / "scene.yaml").string(), "model:=none", "backend:=cpu"});
  ASSERT_TRUE(wait_for([] { return advertised("/real/net_distance"); }, 30s)) << node->log();
  ASSERT_TRUE(connected(distance, yaw)) << node->log();
  ChildProcess play = play_bag(bag, dir() / "play_real.log");
  ASSERT_EQ(play.wait(120s), 0) << play.log();
  wait_for([&] { return distance.size() >= 1 && yaw.size() >= 1; }, 30s);
  ASSERT_EQ(node->stop(30s), 0) << node->log();
  ASSERT_EQ(distance.size(), 1u) << node->log();
  ASSERT_EQ(yaw.size(), 1u);

  const std::vector<EstimateRow> rows = run_estimates(bag, real / "scene.yaml", "real_run");
  ASSERT_EQ(rows.size(), 1u);
  // docs/fft_detection.md: 0.355 m and -9.3 deg on this frame.
  EXPECT_NEAR(rows[0].d_net_fft_m, 0.355, 0.01);
  expect_same(distance.messages()[0].data, rows[0].d_net_fft_m, "net_distance");
  expect_same(yaw.messages()[0].data, rows[0].psi_net_fft_rad, "net_yaw");
}

// With the shipped depth network: ~depth per frame with net priors, at the camera's size, and
// ~map (the occupied voxels in P) while someone listens.
TEST_F(NodeTest, PublishesDenseDepthAndTheMapWithTheShippedModel) {
  ros::NodeHandle nh;
  Recorder<node::msg::Image> depth(nh, "/depth_node/depth");
  Recorder<node::msg::PointCloud2> map(nh, "/depth_node/map");
  Recorder<node::msg::PoseStamped> relative(nh, "/depth_node/relative_pose");
  auto node =
      start_node("depth_node", {scene_param(), "model:=auto", "backend:=cpu", "map_rate_hz:=4.0"});
  ASSERT_TRUE(wait_for([] { return advertised("/depth_node/relative_pose"); }, 30s)) << node->log();
  ASSERT_TRUE(connected(depth, relative)) << node->log();  // ~map is advertised with the camera
  ChildProcess play = play_bag(bag_file(), dir() / "play_depth.log");
  ASSERT_EQ(play.wait(120s), 0) << play.log();
  const size_t frames = original().frames.size();
  // A node slower than the camera drops frames in the subscriber's queue, as live.
  for (size_t seen = SIZE_MAX; relative.size() != seen;) {  // until 5 s without a new one
    seen = relative.size();
    wait_for([&] { return relative.size() != seen; }, 5s);
  }
  ASSERT_EQ(node->stop(60s), 0) << node->log();
  const std::string log = node->log();
  ASSERT_EQ(log.find("dense depth off"), std::string::npos) << log;
  const size_t summary = log.find("frames published");
  ASSERT_NE(summary, std::string::npos) << log;
  std::printf("%s\n", log.substr(summary, log.find('\n', summary) - summary).c_str());
  EXPECT_GE(relative.size(), frames / 2);

  const auto images = depth.messages();
  EXPECT_GE(images.size(), relative.size() / 2);  // frames with net priors
  for (const auto& m : images) {
    EXPECT_EQ(m.encoding, "32FC1");
    EXPECT_EQ(m.width, static_cast<uint32_t>(original().cam0.camera.width_px));
    EXPECT_EQ(m.height, static_cast<uint32_t>(original().cam0.camera.height_px));
    ASSERT_EQ(m.data.size(), size_t{4} * m.width * m.height);
    float centre = 0;
    std::memcpy(&centre, &m.data[4 * (m.width * (m.height / 2) + m.width / 2)], 4);
    EXPECT_TRUE(centre > 0.2f && centre < 5.0f) << centre;  // the net, 0.5-1.5 m ahead
  }
  const auto maps = map.messages();
  ASSERT_FALSE(maps.empty());
  EXPECT_EQ(maps.back().header.frame_id, "pen");
  EXPECT_GT(maps.back().width, 100u);
}

TEST_F(NodeTest, WithoutCameraInfoSaysWhatIsMissingAndKeepsRunning) {
  testing::BagWriteOptions w;
  w.camera_info = false;
  const fs::path bag = dir() / "no_camera_info.bag";
  testing::dataset_to_bag(original(), bag, w);
  auto node = start_node(
      "no_info", {scene_param(), "model:=none", "backend:=cpu", "camera_info_timeout_s:=0.5"});
  ASSERT_TRUE(wait_for([] { return advertised("/no_info/relative_pose"); }, 30s)) << node->log();
  ChildProcess play = play_bag(bag, dir() / "play_no_info.log");
  ASSERT_EQ(play.wait(120s), 0) << play.log();
  EXPECT_TRUE(node->running());
  EXPECT_EQ(node->stop(30s), 0) << node->log();
  const std::string log = node->log();
  EXPECT_NE(log.find("no sensor_msgs/CameraInfo on '/camera/camera_info'"), std::string::npos)
      << log;
  EXPECT_NE(log.find("~camera_yaml"), std::string::npos) << log;
  EXPECT_NE(log.find("0 frames published"), std::string::npos) << log;
}

// Bad frames from a live camera: an encoding the node does not decode, a frame of another size
// than camera_info's, a frame whose data is shorter than height x step. Each is logged with what
// is wrong and skipped; the node keeps running.
TEST_F(NodeTest, BadFramesAreLoggedAndSkipped) {
  ros::NodeHandle nh;
  auto node = start_node("encoding", {scene_param(), "model:=none", "backend:=cpu"});
  ASSERT_TRUE(wait_for([] { return advertised("/encoding/relative_pose"); }, 30s)) << node->log();
  const ros::Publisher info_pub = nh.advertise<msg::CameraInfo>("/camera/camera_info", 1, true);
  const ros::Publisher image_pub = nh.advertise<msg::Image>("/camera/image_raw", 5);
  const PinholeCamera& cam = original().cam0.camera;
  msg::CameraInfo info;
  info.width = static_cast<uint32_t>(cam.width_px);
  info.height = static_cast<uint32_t>(cam.height_px);
  info.K = {cam.fx_px, 0, cam.cx_px, 0, cam.fy_px, cam.cy_px, 0, 0, 1};
  info_pub.publish(info);
  ASSERT_TRUE(wait_for([&] { return image_pub.getNumSubscribers() > 0; }, 30s));
  ASSERT_TRUE(wait_for([&] { return node->log().find("camera, fx") != std::string::npos; }, 30s))
      << node->log();
  msg::Image image;
  image.header.stamp.fromSec(1.0);
  image.width = info.width;
  image.height = info.height;
  image.encoding = "bayer_rggb8";
  image.step = image.width;
  image.data.assign(static_cast<size_t>(image.step) * image.height, 128);
  image_pub.publish(image);
  ASSERT_TRUE(wait_for([&] { return node->log().find("bayer_rggb8") != std::string::npos; }, 30s))
      << node->log();
  image.header.stamp.fromSec(2.0);
  image.encoding = "mono8";
  image.width = 320;
  image.height = 240;
  image.step = image.width;
  image.data.assign(size_t{320} * 240, 128);
  image_pub.publish(image);
  ASSERT_TRUE(wait_for(
      [&] { return node->log().find("image is 320x240 but the camera is") != std::string::npos; },
      30s))
      << node->log();
  image.header.stamp.fromSec(3.0);
  image.width = info.width;
  image.height = info.height;
  image.step = image.width;
  image.data.assign(size_t{1000}, 128);  // far less than height x step
  image_pub.publish(image);
  ASSERT_TRUE(wait_for(
      [&] { return node->log().find("needs a step of at least") != std::string::npos; }, 30s))
      << node->log();
  EXPECT_TRUE(node->running());
  EXPECT_EQ(node->stop(30s), 0) << node->log();
  const std::string log = node->log();
  EXPECT_NE(log.find("mono8"), std::string::npos) << log;  // names what it takes
  EXPECT_NE(log.find("3 refused"), std::string::npos) << log;
}

TEST_F(NodeTest, ABadParameterStopsTheNodeWithItsName) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"mesh_sise_m:=0.03", "~mesh_sise_m: unknown parameter"},
      {"roi_rows:=0", "~roi_rows: 0 is outside >= 1 (rows of the FFT's ROI grid)"},
      {"roi_rows:=2.5", "~roi_rows: takes an integer"},
      {"backend:=gpu", "~backend"},
      {"pen_radius_m:=-12.0", "~pen_radius_m: -12 is outside > 0 m (pen radius"},
      {"sensor_wait_s:=2.5", "~sensor_wait_s: 2.5 is outside 0 to 1 s (how long"},
      {"scene:=/nonexistent/scene.yaml", "/nonexistent/scene.yaml"}};
  for (size_t i = 0; i < cases.size(); ++i) {
    const auto& [param, message] = cases[i];
    auto node = start_node("bad_" + std::to_string(i), {param});
    ASSERT_EQ(node->wait(30s), 2) << param << "\n" << node->log();
    EXPECT_NE(node->log().find(message), std::string::npos) << param << "\n" << node->log();
  }
}

}  // namespace
}  // namespace pensight
