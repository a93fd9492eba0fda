#pragma once
// Helpers of the ROS tests: child processes that are always reaped (no strays even when a test
// fails), a free loopback port, and a private ROS environment (master URI, log and home folders);
// for the live node tests also a private ROS session (master + this process as a node), the
// simulated camera's publishers and recorders of the node's pose topics.
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "conversions.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m::rostest {

namespace fs = std::filesystem;

// A loopback TCP port that was free a moment ago (the kernel picks it).
inline int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof a;
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0)
    throw std::runtime_error("free_port: cannot bind a loopback socket");
  const int port = ntohs(a.sin_port);
  ::close(fd);
  return port;
}

// Points this process (and the children it starts) at a master on 127.0.0.1:port, with ROS's
// log and home folders under `dir` (ROS writes logs; never into the user's ~/.ros).
inline std::string use_private_ros_env(int port, const fs::path& dir) {
  const std::string uri = "http://127.0.0.1:" + std::to_string(port);
  fs::create_directories(dir / "log");
  ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
  ::setenv("ROS_IP", "127.0.0.1", 1);
  ::unsetenv("ROS_HOSTNAME");
  ::setenv("ROS_HOME", dir.c_str(), 1);
  ::setenv("ROS_LOG_DIR", (dir / "log").c_str(), 1);
  return uri;
}

// A child process (its own process group), stopped with SIGINT, then SIGKILL after `grace`, and
// always reaped in the destructor.
class Child {
 public:
  explicit Child(const std::vector<std::string>& argv, const fs::path& log) {
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      ::setpgid(0, 0);
      const std::string out = log.string();
      // One open file for both (dup2): with two, stdout's own offset overwrote what stderr appended.
      if (!freopen(out.c_str(), "w", stdout) || ::dup2(fileno(stdout), STDERR_FILENO) < 0) _exit(126);
      std::vector<char*> args;
      for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execvp(args[0], args.data());
      _exit(127);
    }
    ::setpgid(pid_, pid_);  // also from the parent: no race with a signal sent right after fork
  }
  ~Child() { stop(std::chrono::seconds(5)); }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  bool running() {
    if (pid_ <= 0) return false;
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == 0) return true;
    pid_ = -1;
    status_ = status;
    return false;
  }

  // SIGINT to the group, wait up to `grace`, then SIGKILL. Returns the exit status (waitpid form).
  int stop(std::chrono::milliseconds grace) {
    if (!running()) return status_;
    ::kill(-pid_, SIGINT);
    const auto until = std::chrono::steady_clock::now() + grace;
    while (running() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (running()) {
      ::kill(-pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
      status_ = status;
      killed_ = true;
    }
    return status_;
  }
  bool killed() const { return killed_; }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool killed_ = false;
};

inline std::string read_file(const fs::path& p) {
  std::FILE* f = std::fopen(p.c_str(), "rb");
  if (!f) return "";
  std::string s;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
  std::fclose(f);
  return s;
}

template <typename Pred>
bool wait_for(Pred pred, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return pred();
}

// A private ROS session: a rosmaster on a free loopback port, ROS's files under a fresh temp dir,
// this process initialised as an anonymous ROS node with a spinner thread. roscpp cannot be
// initialised twice in one process: one session per test process (a suite's SetUpTestSuite).
class RosSession {
 public:
  RosSession(const std::string& tag, const std::string& rosmaster)
      : dir_(fs::temp_directory_path() / (tag + "_" + std::to_string(::getpid()))) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const int port = free_port();
    use_private_ros_env(port, dir_);
    master_ = std::make_unique<Child>(std::vector<std::string>{rosmaster, "--core", "-p", std::to_string(port)},
                                      dir_ / "master.log");
    std::string name = tag;
    int argc = 1;
    char* argv[] = {name.data(), nullptr};
    ros::init(argc, argv, tag, ros::init_options::NoSigintHandler | ros::init_options::AnonymousName);
    if (!wait_for([] { return ros::master::check(); }, std::chrono::seconds(30)))
      throw std::runtime_error("rosmaster did not come up:\n" + read_file(dir_ / "master.log"));
    nh_ = std::make_unique<ros::NodeHandle>();
    spinner_ = std::make_unique<ros::AsyncSpinner>(1);
    spinner_->start();
  }
  ~RosSession() {
    spinner_.reset();
    nh_.reset();
    ros::shutdown();
    master_->stop(std::chrono::seconds(10));
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  RosSession(const RosSession&) = delete;
  RosSession& operator=(const RosSession&) = delete;

  const fs::path& dir() const { return dir_; }
  ros::NodeHandle& nh() { return *nh_; }

 private:
  fs::path dir_;
  std::unique_ptr<Child> master_;
  std::unique_ptr<ros::NodeHandle> nh_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
};

// The simulated flight of the node tests: the office scene, hand-held, seed 7, 640x480 at 30 fps.
inline sim::Simulation office_flight(int frames) {
  sim::SimConfig sc;
  sc.scene = "office";
  sc.seed = 7;
  sc.trajectory.type = "handheld";
  sc.trajectory.frames = frames;
  return sim::Simulation(sc);
}

// A frame's stamp as the node sends it back (seconds through ros::Time): the key of PoseRecorder.
inline double stamp_key(double t_s) { return ros1::to_seconds(ros1::to_ros_time(t_s)); }

// How far a driver's depth and label stamps lag the colour stamp [s] (camera_info: none).
struct StampOffsets {
  double depth_s = 0.0;
  double labels_s = 0.0;
};

// The node's inputs from simulated frames, under `ns`: ns/rgb (rgb8), ns/depth (16UC1 mm), ns/info
// (CameraInfo) and, with labels, ns/labels (mono16).
class FramePublisher {
 public:
  FramePublisher(ros::NodeHandle& nh, const std::string& ns, bool labels)
      : rgb_(nh.advertise<sensor_msgs::Image>(ns + "/rgb", 5)),
        depth_(nh.advertise<sensor_msgs::Image>(ns + "/depth", 5)),
        info_(nh.advertise<sensor_msgs::CameraInfo>(ns + "/info", 5)) {
    if (labels) labels_ = nh.advertise<sensor_msgs::Image>(ns + "/labels", 5);
  }
  // Every input topic has at least n subscribers (n nodes have connected).
  bool connected(unsigned n) const {
    return rgb_.getNumSubscribers() >= n && depth_.getNumSubscribers() >= n && info_.getNumSubscribers() >= n &&
           (!labels_ || labels_.getNumSubscribers() >= n);
  }
  // Colour and camera_info stamped f.t_s, depth and labels that plus `offsets` (a driver that does
  // not stamp every image with the same time). Returns the labels message sent (empty without).
  sensor_msgs::Image publish(const RgbdFrame& f, const PinholeCamera& camera, StampOffsets offsets = {}) {
    std_msgs::Header h;
    h.stamp = ros1::to_ros_time(f.t_s);
    h.frame_id = frame_id;
    sensor_msgs::Image c = ros1::bgr_to_msg(f.rgb), d = ros1::depth_to_msg(f.depth_m, "16UC1"), l;
    sensor_msgs::CameraInfo ci = ros1::info_from_camera(camera);
    c.header = d.header = ci.header = h;
    d.header.stamp = ros1::to_ros_time(f.t_s + offsets.depth_s);
    rgb_.publish(c), depth_.publish(d), info_.publish(ci);
    if (labels_) {
      l = ros1::labels_to_msg(f.labels);
      l.header = h;
      l.header.stamp = ros1::to_ros_time(f.t_s + offsets.labels_s);
      labels_.publish(l);
    }
    return l;
  }
  std::string frame_id = "camera_rgb_optical_frame";

 private:
  ros::Publisher rgb_, depth_, info_, labels_;
};

// How many frames an ApproximateTime node has answered once frame i (0-based) is published, when
// the first `offset_frames` frames have offset stamps: it emits a set only once a later message
// proves it the best one, so an offset frame is answered when the next frame arrives (the first
// aligned frame flushes the last offset one); an aligned frame (spread 0) is answered at once.
inline std::size_t approx_answers_due(int i, int offset_frames) {
  return static_cast<std::size_t>(i < offset_frames ? i : i + 1);
}

// Publishes `frames` frames of `sim` lock-step: frame i with `offsets` while i < offset_frames,
// aligned after, then waits (bounded) for answered(i). Once a wait times out the counts the caller
// checks fail anyway, so later waits are short. `on_sent(i, f, labels_msg)` sees each frame sent.
// Returns the ground truth keyed by stamp_key, as the node's answers are.
template <typename Answered, typename OnSent>
io::Trajectory fly_lockstep(FramePublisher& cam, const sim::Simulation& sim, int frames, int offset_frames,
                            StampOffsets offsets, Answered answered, OnSent on_sent) {
  io::Trajectory gt;
  bool behind = false;
  for (int i = 0; i < frames; ++i) {
    const RgbdFrame f = sim.frame(i);
    gt.push_back({stamp_key(f.t_s), sim.trajectory().samples[i].T_w_c});
    on_sent(i, f, cam.publish(f, sim.camera(), i < offset_frames ? offsets : StampOffsets{}));
    const bool ok = wait_for([&] { return answered(i); }, behind ? std::chrono::milliseconds(500)
                                                                 : std::chrono::milliseconds(20000));
    behind = behind || !ok;
  }
  return gt;
}

// Records a geometry_msgs/PoseStamped or nav_msgs/Odometry topic: stamp [s] -> pose, the number of
// messages (a repeated stamp shows as count() > poses().size()) and the last message's frames.
template <typename Msg>
class PoseRecorder {
 public:
  PoseRecorder(ros::NodeHandle& nh, const std::string& topic)
      : sub_(nh.subscribe(topic, 200, &PoseRecorder::on, this)) {}
  bool connected() const { return sub_.getNumPublishers() > 0; }
  std::size_t count() const {
    std::lock_guard l(m_);
    return count_;
  }
  bool has(double t_s) const {
    std::lock_guard l(m_);
    return poses_.count(t_s) > 0;
  }
  std::map<double, SE3> poses() const {
    std::lock_guard l(m_);
    return poses_;
  }
  std::pair<std::string, std::string> frames() const {  // header.frame_id, child_frame_id
    std::lock_guard l(m_);
    return frames_;
  }

 private:
  static const geometry_msgs::Pose& pose_of(const geometry_msgs::PoseStamped& m) { return m.pose; }
  static const geometry_msgs::Pose& pose_of(const nav_msgs::Odometry& m) { return m.pose.pose; }
  static std::string child_of(const geometry_msgs::PoseStamped&) { return ""; }
  static std::string child_of(const nav_msgs::Odometry& m) { return m.child_frame_id; }
  void on(const boost::shared_ptr<const Msg>& m) {
    std::lock_guard l(m_);
    ++count_;
    poses_[ros1::to_seconds(m->header.stamp)] = ros1::from_pose(pose_of(*m));
    frames_ = {m->header.frame_id, child_of(*m)};
  }

  mutable std::mutex m_;
  std::map<double, SE3> poses_;
  std::size_t count_ = 0;
  std::pair<std::string, std::string> frames_;
  ros::Subscriber sub_;  // last: unsubscribed (waiting for a running callback) before the rest goes
};

}  // namespace s3m::rostest
