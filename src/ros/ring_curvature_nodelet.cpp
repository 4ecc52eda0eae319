#include "ring_curvature/ros/ring_curvature_nodelet.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <boost/make_shared.hpp>
#include <chrono>
#include <string>

#include <pluginlib/class_list_macros.hpp>

#include <stdexcept>

#include "ring_curvature/features.hpp"
#include "ring_curvature/ros/param_loading.hpp"

namespace ring_curvature
{

RingCurvatureNodelet::~RingCurvatureNodelet()
{
  // Stop callbacks that reference members before the members go.
  diag_timer_.stop();
  sub_.shutdown();
}

namespace
{
/// The weakest direction in words, e.g. "translation x (0.99), eigenvalue 0.0003 < 0.01".
std::string degeneracyText(const DegeneracyReport& d)
{
  static const char* const names[6] = {"rotation x", "rotation y", "rotation z", "translation x", "translation y", "translation z"};
  std::size_t k = 0;
  for (std::size_t i = 1; i < 6; ++i)
    if (std::fabs(d.weakest_direction[i]) > std::fabs(d.weakest_direction[k])) k = i;
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s (%.2f), eigenvalue %.4g, from %u plane and %u line constraints", names[k],
                std::fabs(d.weakest_direction[k]), d.eigenvalues[0], d.plane_constraints, d.line_constraints);
  return buf;
}

/// Reads an int queue size from the private namespace; < 1 stops the nodelet with a message naming it.
void readQueueSize(const ros::NodeHandle& pnh, const char* name, int& value)
{
  pnh.param(name, value, value);
  if (value < 1)
  {
    ROS_FATAL("parameter '%s' must be >= 1 (got %d)", pnh.resolveName(name).c_str(), value);
    throw std::runtime_error(std::string("ring_curvature: invalid parameter ") + name);
  }
}
}  // namespace

void RingCurvatureNodelet::onInit()
{
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  Params params;
  const Status s = loadParams(pnh, params);
  if (!s)
  {
    // Fail loudly at start-up rather than run with parameters the user did not ask for.
    NODELET_FATAL("invalid parameters: %s", s.message.c_str());
    throw std::runtime_error("ring_curvature: invalid parameters: " + s.message);
  }
  readQueueSize(pnh, "queue_size", queue_size_);
  readQueueSize(pnh, "publish_queue_size", publish_queue_size_);
  processor_ = std::make_unique<FrameProcessor>(params);
  window_start_ = ros::WallTime::now();
  const std::string odometry_topic = pnh.param<std::string>("deskew_odometry", "");
  for (const auto& [name, value] : {std::pair<const char*, double*>{"deskew_max_age", &deskew_max_age_},
                                     std::pair<const char*, double*>{"deskew_window", &deskew_window_}})
  {
    *value = pnh.param(name, *value);
    if (!(*value > 0.0))
    {
      NODELET_FATAL("parameter '%s' must be > 0 s (got %g)", pnh.resolveName(name).c_str(), *value);
      throw std::runtime_error(std::string("ring_curvature: invalid parameter ") + name);
    }
  }
  const std::string reference = pnh.param<std::string>("deskew_reference", "middle");
  if (reference != "middle" && reference != "stamp")
  {
    NODELET_FATAL("parameter '%s' must be middle or stamp (got '%s')", pnh.resolveName("deskew_reference").c_str(),
                  reference.c_str());
    throw std::runtime_error("ring_curvature: invalid parameter deskew_reference");
  }
  if (!odometry_topic.empty())
  {
    processor_->setSweepMiddleReference(reference == "middle");
    // always subscribed: a few poses a second, and the history must be there when clouds come
    odom_sub_ = nh.subscribe<nav_msgs::Odometry>(odometry_topic, 10,
                                                 [this](const nav_msgs::OdometryConstPtr& o) { odometry_.add(*o); });
    if (pnh.param("deskew_use_tf", false)) mounting_ = std::make_unique<LidarMounting>(nh);
    NODELET_INFO("LOAM clouds deskewed to the sweep's %s with the motion on %s%s",
                 reference == "middle" ? "middle (and stamped so)" : "stamp", nh.resolveName(odometry_topic).c_str(),
                 mounting_ ? ", moved to the cloud's frame with tf" : " (its child frame taken as the LiDAR's)");
  }

  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<RingCurvatureConfig>>(reconfigure_mutex_, pnh);
  // Start from the loaded parameters, not the .cfg defaults.
  reconfigure_->updateConfig(toConfig(params));
  reconfigure_->setCallback(
      [this](RingCurvatureConfig& config, uint32_t level) { reconfigureCb(config, level); });

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("none");
  updater_->add("processing", this, &RingCurvatureNodelet::diagnose);
  diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { updater_->update(); });

  const ros::SubscriberStatusCallback cb = [this](const ros::SingleSubscriberPublisher&) { connectCb(); };
  std::lock_guard<std::mutex> lock(connect_mutex_);
  // Intra-process subscribers get every message whatever the queue; the queue only decides what a
  // subscriber in another process loses when it reads slower than the sensor.
  const auto q = static_cast<std::uint32_t>(publish_queue_size_);
  pub_labelled_ = pnh.advertise<sensor_msgs::PointCloud2>("labelled_points", q, cb, cb);
  pub_primitives_ = pnh.advertise<PrimitiveArray>("primitives", q, cb, cb);
  pub_edges_ = pnh.advertise<sensor_msgs::PointCloud2>("edges", q, cb, cb);
  pub_planes_ = pnh.advertise<sensor_msgs::PointCloud2>("planes", q, cb, cb);
  pub_markers_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", q, cb, cb);
  pub_stats_ = pnh.advertise<FrameStats>("frame_stats", std::max(q, 10U), cb, cb);
  // LOAM's five inputs (launch/aloam_frontend.launch maps them onto A-LOAM's topic names).
  pub_loam_cloud_ = pnh.advertise<sensor_msgs::PointCloud2>("loam/cloud", q, cb, cb);
  pub_sharp_ = pnh.advertise<sensor_msgs::PointCloud2>("loam/sharp", q, cb, cb);
  pub_less_sharp_ = pnh.advertise<sensor_msgs::PointCloud2>("loam/less_sharp", q, cb, cb);
  pub_flat_ = pnh.advertise<sensor_msgs::PointCloud2>("loam/flat", q, cb, cb);
  pub_less_flat_ = pnh.advertise<sensor_msgs::PointCloud2>("loam/less_flat", q, cb, cb);
  NODELET_INFO("ready: subscribes to %s lazily (while an output has subscribers), outputs in %s",
               nh.resolveName("velodyne_points").c_str(), pnh.getNamespace().c_str());
  // which SIMD clones this CPU runs (docs/performance.md, "SIMD")
  NODELET_INFO("core loops: %s", coreLoopsIsa());
}

void RingCurvatureNodelet::connectCb()
{
  std::lock_guard<std::mutex> lock(connect_mutex_);
  const bool wanted = pub_labelled_.getNumSubscribers() + pub_primitives_.getNumSubscribers() +
                          pub_edges_.getNumSubscribers() + pub_planes_.getNumSubscribers() +
                          pub_markers_.getNumSubscribers() + pub_stats_.getNumSubscribers() +
                          pub_loam_cloud_.getNumSubscribers() + pub_sharp_.getNumSubscribers() +
                          pub_less_sharp_.getNumSubscribers() + pub_flat_.getNumSubscribers() +
                          pub_less_flat_.getNumSubscribers() >
                      0;
  if (wanted && !sub_)
  {
    {
      std::lock_guard<std::mutex> stats_lock(process_mutex_);
      stats_.have_last_seq = false;  // frames published while unsubscribed were not dropped
    }
    sub_ = getNodeHandle().subscribe("velodyne_points", static_cast<std::uint32_t>(queue_size_),
                                     &RingCurvatureNodelet::cloudCb, this);
    subscribed_ = true;
  }
  else if (!wanted && sub_)
  {
    sub_.shutdown();
    subscribed_ = false;
  }
}

void RingCurvatureNodelet::cloudCb(const sensor_msgs::PointCloud2ConstPtr& msg)
{
  // Nothing may escape a callback: in a manager an exception would take down every nodelet.
  const auto t_entry = std::chrono::steady_clock::now();
  try
  {
    OutputSelection select;
    select.labelled = pub_labelled_.getNumSubscribers() > 0;
    select.primitives = pub_primitives_.getNumSubscribers() > 0;
    select.edges = pub_edges_.getNumSubscribers() > 0;
    select.planes = pub_planes_.getNumSubscribers() > 0;
    select.markers = pub_markers_.getNumSubscribers() > 0;
    select.loam_cloud = pub_loam_cloud_.getNumSubscribers() > 0;
    select.sharp = pub_sharp_.getNumSubscribers() > 0;
    select.less_sharp = pub_less_sharp_.getNumSubscribers() > 0;
    select.flat = pub_flat_.getNumSubscribers() > 0;
    select.less_flat = pub_less_flat_.getNumSubscribers() > 0;

    Outputs out;
    Status s;
    {
      std::lock_guard<std::mutex> lock(process_mutex_);
      ++stats_.frames_received;
      ++frames_in_window_;
      const std::uint32_t seq = msg->header.seq;
      if (stats_.have_last_seq && seq > stats_.last_seq + 1 && seq - stats_.last_seq < 100000u)
        stats_.frames_dropped += seq - stats_.last_seq - 1;  // a restart (seq decreasing) is not a drop
      stats_.have_last_seq = true;
      stats_.last_seq = seq;
      stats_.last_input_msg = msg.get();
      SweepMotion motion;
      const bool deskew = odom_sub_ && deskewMotion(msg->header, motion);
      processor_->setSweepMotion(deskew ? &motion : nullptr);
      s = processor_->process(msg, out, select);
      if (s)
      {
        ++stats_.frames_processed;
        stats_.last_input_data = processor_->lastInputData();
        last_summary_ = processor_->summary();
        for (int l = 0; l < kNumLabels; ++l)
          label_totals_[l] += last_summary_.label_counts[l];
        if (last_summary_.loam && last_summary_.degeneracy.degenerate) ++degenerate_frames_;
        if (last_summary_.deskewed) ++deskewed_frames_;
        stats_.last_labelled = out.labelled.get();
        stats_.last_primitives = out.primitives.get();
        stats_.last_edges = out.edges.get();
        stats_.last_planes = out.planes.get();
      }
      else
      {
        ++stats_.frames_rejected;
        stats_.last_error = s.message;
      }
    }
    if (!s)
    {
      NODELET_ERROR_THROTTLE(5.0, "frame rejected (stamp %.6f, frame '%s'): %s", msg->header.stamp.toSec(),
                             msg->header.frame_id.c_str(), s.message.c_str());
      return;
    }
    publishOutputs(out);
    if (pub_stats_.getNumSubscribers() > 0) publishStats(msg->header, t_entry);
  }
  catch (const std::exception& e)
  {
    {
      std::lock_guard<std::mutex> lock(process_mutex_);
      ++stats_.frames_rejected;
      stats_.last_error = e.what();
    }
    NODELET_ERROR_THROTTLE(5.0, "frame dropped: %s", e.what());
  }
}

void RingCurvatureNodelet::publishStats(const std_msgs::Header& header, std::chrono::steady_clock::time_point t_entry)
{
  auto st = boost::make_shared<FrameStats>();
  {
    std::lock_guard<std::mutex> lock(process_mutex_);
    const FrameSummary& s = last_summary_;
    st->header = header;
    st->points = static_cast<std::uint32_t>(s.points);
    for (int l = 0; l < kNumLabels; ++l) st->label_counts[static_cast<std::size_t>(l)] = static_cast<std::uint32_t>(s.label_counts[static_cast<std::size_t>(l)]);
    st->primitives = static_cast<std::uint32_t>(s.primitives);
    st->grid_ms = static_cast<float>(s.grid_ms);
    st->features_ms = static_cast<float>(s.features_ms);
    st->thresholds_ms = static_cast<float>(s.thresholds_ms);
    st->classification_ms = static_cast<float>(s.classification_ms);
    st->primitives_ms = static_cast<float>(s.primitives_ms);
    st->core_output_ms = static_cast<float>(s.core_output_ms);
    st->messages_ms = static_cast<float>(s.messages_ms);
    st->loam = s.loam;
    st->sharp = static_cast<std::uint32_t>(s.sharp);
    st->less_sharp = static_cast<std::uint32_t>(s.less_sharp);
    st->flat = static_cast<std::uint32_t>(s.flat);
    st->less_flat = static_cast<std::uint32_t>(s.less_flat);
    st->loam_ms = static_cast<float>(s.loam_ms);
    st->plane_constraints = s.degeneracy.plane_constraints;
    st->line_constraints = s.degeneracy.line_constraints;
    for (std::size_t i = 0; i < 6; ++i)
    {
      st->degeneracy_eigenvalues[i] = s.degeneracy.eigenvalues[i];
      st->weakest_direction[i] = s.degeneracy.weakest_direction[i];
    }
    st->degenerate = s.loam && s.degeneracy.degenerate;
    st->deskewed = s.deskewed;
  }
  st->callback_ms = static_cast<float>(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_entry).count());
  pub_stats_.publish(st);
}

bool RingCurvatureNodelet::deskewMotion(const std_msgs::Header& header, SweepMotion& motion)
{
  Eigen::Isometry3d lidar_in_child;
  if (mounting_)
  {
    odometry_.childFrame(odom_child_frame_);
    if (!mounting_->lidarInChild(odom_child_frame_, header.frame_id, lidar_in_child, deskew_issue_))
    {
      // a base's motion is not the LiDAR's: rather no deskew than a wrong one
      NODELET_WARN_THROTTLE(5.0, "LOAM clouds not deskewed: %s", deskew_issue_.c_str());
      return false;
    }
  }
  deskew_issue_.clear();
  return odometry_.motionFor(header.stamp, processor_->params().scan_period, deskew_window_, deskew_max_age_, motion,
                             mounting_ ? &lidar_in_child : nullptr);
}

void RingCurvatureNodelet::publishOutputs(Outputs& out)
{
  // Shared-pointer publish: subscribers in the same manager get these very objects. The Ptrs
  // are dropped right after, so nothing here touches a message once it is out.
  if (out.labelled)
    pub_labelled_.publish(out.labelled);
  if (out.primitives)
    pub_primitives_.publish(out.primitives);
  if (out.edges)
    pub_edges_.publish(out.edges);
  if (out.planes)
    pub_planes_.publish(out.planes);
  if (out.markers)
    pub_markers_.publish(out.markers);
  if (out.loam_cloud) pub_loam_cloud_.publish(out.loam_cloud);
  if (out.sharp) pub_sharp_.publish(out.sharp);
  if (out.less_sharp) pub_less_sharp_.publish(out.less_sharp);
  if (out.flat) pub_flat_.publish(out.flat);
  if (out.less_flat) pub_less_flat_.publish(out.less_flat);
  out = Outputs();
}

void RingCurvatureNodelet::reconfigureCb(RingCurvatureConfig& config, uint32_t /*level*/)
{
  std::lock_guard<std::mutex> lock(process_mutex_);
  const Params next = fromConfig(config, processor_->params());
  const Status s = processor_->setParams(next);
  if (!s)
  {
    NODELET_ERROR("reconfigure rejected, previous parameters kept: %s", s.message.c_str());
    // dynamic_reconfigure publishes the config as left by this callback: show what is in force.
    config = toConfig(processor_->params());
    return;
  }
  NODELET_DEBUG("parameters reconfigured");
}

void RingCurvatureNodelet::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat)
{
  std::lock_guard<std::mutex> lock(process_mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const double dt = (now - window_start_).toSec();
  const double rate = dt > 0 ? static_cast<double>(frames_in_window_) / dt : 0.0;
  frames_in_window_ = 0;
  window_start_ = now;

  if (!subscribed_)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "idle: no subscribers to any output");
  else if (stats_.frames_rejected > 0 && !stats_.last_error.empty())
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "frames rejected: " + stats_.last_error);
  else if (last_summary_.loam && last_summary_.degeneracy.degenerate)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "LOAM features degenerate: " + degeneracyText(last_summary_.degeneracy));
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");

  stat.add("input rate [Hz]", rate);
  stat.add("frames received", stats_.frames_received);
  stat.add("frames processed", stats_.frames_processed);
  stat.add("frames rejected", stats_.frames_rejected);
  stat.add("frames dropped by the input queue (header.seq gaps)", stats_.frames_dropped);
  stat.add("last rejection", stats_.last_error.empty() ? std::string("none") : stats_.last_error);
  const FrameSummary& f = last_summary_;
  stat.add("time grid [ms]", f.grid_ms);
  stat.add("time features [ms]", f.features_ms);
  stat.add("time thresholds [ms]", f.thresholds_ms);
  stat.add("time classification [ms]", f.classification_ms);
  stat.add("time primitives [ms]", f.primitives_ms);
  stat.add("time core output [ms]", f.core_output_ms);
  stat.add("time messages [ms]", f.messages_ms);
  stat.add("time total [ms]", f.coreMs() + f.messages_ms);
  stat.add("primitives (last frame)", f.primitives);
  if (f.loam)
  {
    stat.add("LOAM sharp / less sharp / flat / less flat (last frame)",
             std::to_string(f.sharp) + " / " + std::to_string(f.less_sharp) + " / " + std::to_string(f.flat) + " / " +
                 std::to_string(f.less_flat));
    stat.add("LOAM weakest direction (last frame)", degeneracyText(f.degeneracy));
  }
  stat.add("LOAM frames degenerate", degenerate_frames_);
  if (odom_sub_) stat.add("LOAM frames deskewed", deskewed_frames_);
  if (!deskew_issue_.empty()) stat.add("LOAM deskew", deskew_issue_);
  for (int l = 0; l < kNumLabels; ++l)
    stat.add(std::string("points labelled ") + labelName(static_cast<Label>(l)), label_totals_[l]);
}

NodeletStats RingCurvatureNodelet::stats() const
{
  std::lock_guard<std::mutex> lock(process_mutex_);
  return stats_;
}

}  // namespace ring_curvature

PLUGINLIB_EXPORT_CLASS(ring_curvature::RingCurvatureNodelet, nodelet::Nodelet)
