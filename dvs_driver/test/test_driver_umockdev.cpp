// rostest: the driver nodelet, loaded in this process, streams from an emulated DVS128
// (umockdev, the real libusb path) onto /dvs/events; biases follow dynamic_reconfigure; the
// master publishes its reset time; an unplug/replug mid-stream recovers. Every generated event,
// from the very first, must arrive in order: the subscription exists before the driver.
#include "emulator/dvs128_emulator.h"

#include <dvs_driver/dvs128_decoder.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_msgs/EventArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <std_msgs/Time.h>

#include <sensor_msgs/SetCameraInfo.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <unistd.h>

using dvs_driver_test::Dvs128Emulator;

namespace
{
Dvs128Emulator* g_emu = nullptr;
int64_t g_load_ns = 0;  // ROS time just before the driver nodelet was loaded
const std::string g_calib_dir = "/tmp/dvs_driver_umockdev_calib_" + std::to_string(::getpid());

struct Received
{
  std::mutex mutex;
  uint64_t events = 0;
  uint64_t next = 0;          // index of the next generated event expected
  uint64_t mismatches = 0;
  int64_t first_mismatch = -1;      // index expected at the first mismatch
  int64_t first_mismatch_got = -1;  // generated index (mod 32768) of the event received there
  uint64_t backwards = 0;
  int64_t last_stamp = 0;
  int64_t first_stamp = -1;
  std::vector<ros::Time> resets;
} g_rx;

void onEvents(const dvs_msgs::EventArrayConstPtr& msg)
{
  std::lock_guard<std::mutex> lock(g_rx.mutex);
  for (const auto& e : msg->events)
  {
    uint16_t x, y;
    bool p;
    dvs_driver::decodeDvs128Address(dvs_driver_test::generatedAddress(g_rx.next), x, y, p);
    if (e.x != x || e.y != y || e.polarity != p)
    {
      if (g_rx.mismatches++ == 0)
      {
        g_rx.first_mismatch = static_cast<int64_t>(g_rx.next);
        g_rx.first_mismatch_got = (127 - e.x) + 128 * (127 - e.y) + (e.polarity ? 0 : 16384);
      }
    }
    ++g_rx.next;
    const int64_t s = dvs_driver::rosTimeToNs(e.ts);
    if (s < g_rx.last_stamp)
      ++g_rx.backwards;
    g_rx.last_stamp = s;
    if (g_rx.first_stamp < 0)
      g_rx.first_stamp = s;
    ++g_rx.events;
  }
}

void onReset(const std_msgs::TimeConstPtr& msg)
{
  std::lock_guard<std::mutex> lock(g_rx.mutex);
  g_rx.resets.push_back(msg->data);
}

// Where the received sequence first left the generated one (for failure messages).
std::string firstMismatch()
{
  return "first mismatch at generated event " + std::to_string(g_rx.first_mismatch) + " (" +
         std::to_string(g_rx.first_mismatch % 32768) + " mod 32768), received event " +
         std::to_string(g_rx.first_mismatch_got) + " mod 32768; " + std::to_string(g_rx.events) + " events received";
}

uint64_t received()
{
  std::lock_guard<std::mutex> lock(g_rx.mutex);
  return g_rx.events;
}

template <class Pred>
bool waitFor(Pred pred, double seconds)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < end)
  {
    if (pred())
      return true;
    ros::WallDuration(0.005).sleep();
  }
  return pred();
}
}  // namespace

TEST(DriverUmockdev, EmulatedCameraStreamsReconfiguresAndRecovers)
{
  ASSERT_TRUE(waitFor([] { return received() >= 20000; }, 20.0)) << "events: " << received();

  {
    std::lock_guard<std::mutex> lock(g_rx.mutex);
    ASSERT_EQ(1u, g_rx.resets.size());
    const int64_t reset = dvs_driver::rosTimeToNs(g_rx.resets[0]);
    // Stamps = reset time + device microseconds: the few events sent between the start request
    // and the reset carry the start-up time base (after the driver was loaded, before the reset);
    // the rest come after.
    EXPECT_GE(g_rx.first_stamp, g_load_ns);
    EXPECT_LE(g_load_ns, reset);
    EXPECT_GE(g_rx.last_stamp, reset);
    EXPECT_LE(g_rx.last_stamp, dvs_driver::rosTimeToNs(ros::Time::now()) + 50000000LL);
    EXPECT_EQ(0u, g_rx.backwards);
    EXPECT_EQ(0u, g_rx.mismatches) << firstMismatch();  // the generated sequence, nothing lost or reordered
  }
  // Start sequence with the fast preset.
  const auto c = g_emu->controls();
  ASSERT_GE(c.size(), 4u);
  EXPECT_EQ(0xB8, c[0].request);
  EXPECT_EQ(0x00, c[0].data[0]);
  EXPECT_EQ(0x07, c[0].data[1]);
  EXPECT_EQ(0xC8, c[0].data[2]);  // cas 1992
  EXPECT_EQ(0xB3, c[2].request);
  EXPECT_EQ(0xBB, c[3].request);

  // camera_info_manager under the name DVS128-<serial>: set_camera_info stores the calibration
  // in the ${NAME} file of ~camera_info_url.
  sensor_msgs::SetCameraInfo cal;
  cal.request.camera_info.width = 128;
  cal.request.camera_info.height = 128;
  cal.request.camera_info.distortion_model = "plumb_bob";
  cal.request.camera_info.D = {0.1, -0.2, 0.0, 0.0, 0.0};
  cal.request.camera_info.K = {150, 0, 64, 0, 151, 63, 0, 0, 1};
  cal.request.camera_info.P = {150, 0, 64, 0, 0, 151, 63, 0, 0, 0, 1, 0};
  ASSERT_TRUE(ros::service::waitForService("/dvs/set_camera_info", 5000));
  ASSERT_TRUE(ros::service::call("/dvs/set_camera_info", cal));
  EXPECT_TRUE(cal.response.success) << cal.response.status_message;
  std::ifstream stored(g_calib_dir + "/DVS128-EMU00042.yaml");
  ASSERT_TRUE(stored.good()) << "no " << g_calib_dir << "/DVS128-EMU00042.yaml";
  const std::string text((std::istreambuf_iterator<char>(stored)), std::istreambuf_iterator<char>());
  EXPECT_NE(std::string::npos, text.find("camera_name: DVS128-EMU00042")) << text;

  // dynamic_reconfigure: diffOn = 0x0A0B0C reaches the camera.
  g_emu->clearControls();
  dynamic_reconfigure::Reconfigure srv;
  dynamic_reconfigure::IntParameter p;
  p.name = "diffOn";
  p.value = 0x0A0B0C;
  srv.request.config.ints.push_back(p);
  ASSERT_TRUE(ros::service::call("/dvs_driver/set_parameters", srv));
  ASSERT_TRUE(waitFor([] { return !g_emu->controls().empty(); }, 5.0));
  const auto c2 = g_emu->controls();
  EXPECT_EQ(0xB8, c2[0].request);
  EXPECT_EQ(0x0A, c2[0].data[24]);
  EXPECT_EQ(0x0B, c2[0].data[25]);
  EXPECT_EQ(0x0C, c2[0].data[26]);

  // Unplug mid-stream, replug: streaming resumes with the changed bias.
  g_emu->unplug();
  ros::WallDuration(0.5).sleep();
  const uint64_t before = received();
  g_emu->clearControls();
  g_emu->plug();
  ASSERT_TRUE(waitFor([&] { return received() >= before + 20000; }, 20.0)) << "no events after replug";
  const auto c3 = g_emu->controls();
  ASSERT_GE(c3.size(), 4u);
  EXPECT_EQ(0xB8, c3[0].request);
  EXPECT_EQ(0x0A, c3[0].data[24]);
  std::lock_guard<std::mutex> lock(g_rx.mutex);
  EXPECT_EQ(2u, g_rx.resets.size());  // the master reset again after the replug
  EXPECT_EQ(0u, g_rx.backwards);      // stamps stay monotonic across the replug
  EXPECT_EQ(0u, g_rx.mismatches) << firstMismatch();  // no event lost across the replug
}

TEST(DriverUmockdevSlave, FollowsTheMastersResetTime)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(waitFor([] { return received() >= 5000; }, 20.0)) << "events: " << received();
  // Slave start: biases, slave mode, start, and no reset of its own.
  const auto c = g_emu->controls();
  ASSERT_EQ(3u, c.size());
  EXPECT_EQ(0xB8, c[0].request);
  EXPECT_EQ(0xBE, c[1].request);
  EXPECT_EQ(0, c[1].value);
  EXPECT_EQ(0xB3, c[2].request);

  // The master's reset time arrives: the slave resets its camera and stamps from that time on.
  ros::Publisher pub = nh.advertise<std_msgs::Time>("/dvs/reset_timestamps", 1, true);
  std_msgs::Time master_reset;
  master_reset.data = ros::Time::now() + ros::Duration(100.0);  // distinguishable from local time
  g_emu->clearControls();
  pub.publish(master_reset);
  ASSERT_TRUE(waitFor([] { return !g_emu->controls().empty(); }, 10.0)) << "no reset sent";
  EXPECT_EQ(0xBB, g_emu->controls()[0].request);
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(g_rx.mutex);
        return g_rx.last_stamp >= dvs_driver::rosTimeToNs(master_reset.data);
      },
      10.0));
  std::lock_guard<std::mutex> lock(g_rx.mutex);
  // Stamps are the master's reset time + device time: within a few seconds after it.
  EXPECT_LT(g_rx.last_stamp, dvs_driver::rosTimeToNs(master_reset.data) + 5000000000LL);
  EXPECT_EQ(0u, g_rx.backwards);
  EXPECT_EQ(0u, g_rx.mismatches) << firstMismatch();
}

int main(int argc, char** argv)
{
  dvs_driver_test::reexecUnderUmockdev(argc, argv);
  testing::InitGoogleTest(&argc, argv);
  Dvs128Emulator emu("EMU00042", 14);  // before libusb starts in the nodelet
  emu.setEventRate(200000);
  g_emu = &emu;
  ros::init(argc, argv, "test_driver_umockdev");
  ros::NodeHandle nh;
  bool master = true;
  ros::param::param("~master", master, true);
  // The master opens the first camera found (its camera name comes from the serial read over
  // USB); the slave asks for the serial.
  ros::param::set("/dvs_driver/serial_number", std::string(master ? "" : "EMU00042"));
  ros::param::set("/dvs_driver/reconnect_interval", 0.05);
  ros::param::set("/dvs_driver/camera_info_url", "file://" + g_calib_dir + "/${NAME}.yaml");
  ros::param::set("/dvs_driver/master", master);
  // Subscribe before the driver exists: it streams as soon as it is loaded and builds no packet
  // while nobody listens, so a later subscriber would miss the first generated events. A
  // subscription in this process is connected by the driver's advertise(), before its input
  // starts. The queue holds minutes of 1 ms packets: a starved callback thread loses nothing.
  ros::Subscriber sub = nh.subscribe("/dvs/events", 1000000, onEvents);
  ros::Subscriber rsub = nh.subscribe("/dvs/reset_timestamps", 10, onReset);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  nodelet::Loader loader(false);
  const nodelet::M_string remap;
  const nodelet::V_string args;
  g_load_ns = dvs_driver::rosTimeToNs(ros::Time::now());
  if (!loader.load("/dvs_driver", "dvs_driver/DriverNodelet", remap, args))
  {
    ADD_FAILURE() << "cannot load dvs_driver/DriverNodelet";
    return 1;
  }
  const int r = RUN_ALL_TESTS();
  loader.unload("/dvs_driver");
  std::filesystem::remove_all(g_calib_dir);
  return r;
}
