// rostest: the calibration node (or nodelet) on an emulated recording published on /dvs/events:
// previews and focus scores come out, views are kept, ~calibrate recovers the camera and sends
// it to /dvs/set_camera_info, ~save writes the YAML, ~reset forgets the views.
#include "emulated_screen.h"

#include <dvs_calibration/calibration_ros.h>
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event_bag_io.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/SetCameraInfo.h>
#include <std_msgs/Float64.h>
#include <std_msgs/UInt32.h>
#include <std_srvs/Trigger.h>

#include <atomic>
#include <fstream>

using namespace dvs_calibration;

namespace
{
std::atomic<int> previews{0}, scores{0};
std::atomic<uint32_t> views{0};
sensor_msgs::CameraInfo received_info;
std::atomic<bool> info_received{false};

bool setCameraInfo(sensor_msgs::SetCameraInfo::Request& req, sensor_msgs::SetCameraInfo::Response& res)
{
  received_info = req.camera_info;
  info_received = true;
  res.success = true;
  return true;
}

void onPreview(const sensor_msgs::ImageConstPtr& m)
{
  if (m->width == 512 && m->height == 512 && m->encoding == "bgr8")
    ++previews;
}
void onScore(const std_msgs::Float64ConstPtr& m)
{
  if (m->data >= 0)
    ++scores;
}
void onViews(const std_msgs::UInt32ConstPtr& m) { views = m->data; }

bool call(const std::string& name, std_srvs::Trigger::Response& res)
{
  ros::NodeHandle nh;
  ros::ServiceClient c = nh.serviceClient<std_srvs::Trigger>(name);
  if (!c.waitForExistence(ros::Duration(20)))
    return false;
  std_srvs::Trigger srv;
  const bool ok = c.call(srv);
  res = srv.response;
  return ok;
}
}  // namespace

TEST(CalibrationNode, CalibratesFromPublishedEvents)
{
  ros::NodeHandle nh;
  ros::ServiceServer server = nh.advertiseService("/dvs/set_camera_info", setCameraInfo);
  ros::Subscriber s1 = nh.subscribe("/dvs_calibration/preview", 10, onPreview);
  ros::Subscriber s2 = nh.subscribe("/dvs_calibration/focus_score", 100, onScore);
  ros::Subscriber s3 = nh.subscribe("/dvs_calibration/views", 10, onViews);
  ros::Publisher pub = nh.advertise<dvs_msgs::EventArray>("/dvs/events", 1000);
  ros::AsyncSpinner spinner(2);
  spinner.start();

  // Wait for the node to subscribe.
  for (int i = 0; i < 200 && pub.getNumSubscribers() == 0; ++i)
    ros::Duration(0.05).sleep();
  ASSERT_GT(pub.getNumSubscribers(), 0u);
  for (int i = 0; i < 100 && s1.getNumPublishers() == 0; ++i)
    ros::Duration(0.05).sleep();

  dvs_calibration::testing::EmulatedScreen screen;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 12, 40.0, 41);
  const auto events = dvs_calibration::testing::emulateRecording(screen, poses, 400000000, 100000000, 41);
  // Packets of 10 ms, paced so that the subscriber queue never overflows.
  size_t begin = 0;
  while (begin < events.size())
  {
    size_t end = begin;
    const int64_t limit = (events[begin].t_ns / 10000000 + 1) * 10000000;
    while (end < events.size() && events[end].t_ns < limit)
      ++end;
    pub.publish(dvs_driver::toMessage(events.data() + begin, events.data() + end, 128, 128));
    begin = end;
    ros::Duration(0.005).sleep();
  }
  // The node works through its queue; the latched view count arrives asynchronously.
  for (int i = 0; i < 200 && views.load() < 10u; ++i)
    ros::Duration(0.05).sleep();

  EXPECT_GT(previews.load(), 10);
  EXPECT_GT(scores.load(), 50);
  EXPECT_GE(views.load(), 10u);

  std_srvs::Trigger::Response res;
  ASSERT_TRUE(call("/dvs_calibration/calibrate", res));
  ASSERT_TRUE(res.success) << res.message;
  EXPECT_NE(res.message.find("\"rms_px\":"), std::string::npos) << res.message;
  for (int i = 0; i < 100 && !info_received; ++i)
    ros::Duration(0.05).sleep();
  ASSERT_TRUE(info_received.load());
  EXPECT_EQ(received_info.distortion_model, "plumb_bob");
  EXPECT_EQ(received_info.width, 128u);
  EXPECT_NEAR(received_info.K[0], 115.0, 1.15);
  EXPECT_NEAR(received_info.K[2], 63.5, 1.5);
  EXPECT_NEAR(received_info.D[0], -0.12, 0.03);

  ASSERT_TRUE(call("/dvs_calibration/save", res));
  ASSERT_TRUE(res.success) << res.message;
  const CameraModel saved = loadCameraInfoYaml(res.message);
  EXPECT_NEAR(saved.intrinsics().fx, received_info.K[0], 1e-6);

  ASSERT_TRUE(call("/dvs_calibration/reset", res));
  EXPECT_TRUE(res.success);
  ASSERT_TRUE(call("/dvs_calibration/calibrate", res));
  EXPECT_FALSE(res.success);  // no views left
  EXPECT_NE(res.message.find("\"error\":"), std::string::npos) << res.message;
  ASSERT_TRUE(call("/dvs_calibration/save", res));
  EXPECT_FALSE(res.success);  // nothing calibrated since the reset
}

TEST(CalibrationNode, RejectsBadParametersNamingThem)
{
  const std::vector<std::pair<std::string, XmlRpc::XmlRpcValue>> bad = {
    {"spacing", XmlRpc::XmlRpcValue(-0.1)},       {"grid", XmlRpc::XmlRpcValue("7by7")},
    {"detector", XmlRpc::XmlRpcValue("hough")},   {"window", XmlRpc::XmlRpcValue(0.0)},
    {"closing_size", XmlRpc::XmlRpcValue(40)},    {"min_views", XmlRpc::XmlRpcValue(1)},
    {"width", XmlRpc::XmlRpcValue(128)},  // width without height
  };
  for (size_t i = 0; i < bad.size(); ++i)
  {
    const std::string ns = "/bad_parameters_" + std::to_string(i);
    ros::NodeHandle pnh(ns);
    pnh.setParam(bad[i].first, bad[i].second);
    try
    {
      dvs_calibration::CalibrationRos node(ros::NodeHandle(ns + "_global"), pnh);
      ADD_FAILURE() << "accepted bad " << bad[i].first;
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string(e.what()).find(bad[i].first), std::string::npos) << e.what();
    }
  }
  // A parameter of the wrong type is named too.
  ros::NodeHandle typed("/bad_type");
  typed.setParam("max_views", "many");
  try
  {
    dvs_calibration::CalibrationRos node(ros::NodeHandle("/bad_type_global"), typed);
    ADD_FAILURE() << "accepted a string for max_views";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("~max_views must be an integer"), std::string::npos) << e.what();
  }
  // The deprecated ~window_ms (ms) is still read, converted to seconds.
  ros::NodeHandle old_name("/old_window_ms");
  old_name.setParam("window_ms", 0.0);
  EXPECT_THROW(dvs_calibration::CalibrationRos(ros::NodeHandle("/old_global"), old_name), std::invalid_argument);
  old_name.setParam("window_ms", 50.0);
  EXPECT_NO_THROW(dvs_calibration::CalibrationRos(ros::NodeHandle("/old_global"), old_name));
  // The defaults are valid.
  ros::NodeHandle good("/good_parameters");
  EXPECT_NO_THROW(dvs_calibration::CalibrationRos(ros::NodeHandle("/good_global"), good));
}

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_calibration_node");
  return RUN_ALL_TESTS();
}
