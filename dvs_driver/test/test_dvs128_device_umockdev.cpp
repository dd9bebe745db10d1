// The real libusb code path of Dvs128Device against an emulated DVS128 (umockdev). The binary
// re-executes itself under umockdev-wrapper (LD_PRELOAD of libumockdev-preload).
#include "emulator/dvs128_emulator.h"

#include <dvs_driver/dvs128_decoder.h>
#include <dvs_driver/dvs128_device.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

using dvs_driver_test::ControlRecord;
using dvs_driver_test::Dvs128Emulator;
using namespace std::chrono_literals;

namespace
{
// Decodes on the device thread and checks every event is the next generated one.
struct CheckingListener : dvs_driver::Dvs128Listener, dvs_driver::Dvs128ConsumerBase
{
  dvs_driver::Dvs128Decoder decoder;
  std::atomic<uint64_t> events{0};
  std::atomic<uint64_t> out_of_order{0};
  std::atomic<int> connects{0}, disconnects{0}, resets_sent{0};
  uint64_t next = 0;
  std::mutex mutex;
  std::string last_disconnect;

  void onData(const uint8_t* data, size_t size) override { decoder.decode(data, size, *this); }
  void event(int64_t, uint16_t x, uint16_t y, bool pol)
  {
    const uint16_t a = dvs_driver_test::generatedAddress(next);
    uint16_t ex, ey;
    bool ep;
    dvs_driver::decodeDvs128Address(a, ex, ey, ep);
    if (x != ex || y != ey || pol != ep)
      ++out_of_order;
    ++next;
    ++events;
  }
  void onConnected(const dvs_driver::Dvs128DeviceInfo&) override
  {
    decoder.reset();
    ++connects;
  }
  void onDisconnected(const std::string& why) override
  {
    std::lock_guard<std::mutex> lock(mutex);
    last_disconnect = why;
    ++disconnects;
  }
  void onTimestampResetRequest() override { ++resets_sent; }
};

template <class Pred>
bool waitFor(Pred pred, std::chrono::milliseconds timeout = 5000ms)
{
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end)
  {
    if (pred())
      return true;
    std::this_thread::sleep_for(5ms);
  }
  return pred();
}

std::vector<uint8_t> vendorRequests(const std::vector<ControlRecord>& c)
{
  std::vector<uint8_t> r;
  for (const auto& x : c)
    r.push_back(x.request);
  return r;
}
}  // namespace

TEST(Dvs128DeviceUmockdev, EnumeratesWithSerialAndFirmware)
{
  Dvs128Emulator emu("EMU00042", 14);
  CheckingListener l;
  dvs_driver::Dvs128Device dev(dvs_driver::Dvs128DeviceOptions(), l);
  const auto list = dev.listDevices();
  ASSERT_EQ(1u, list.size());
  EXPECT_EQ("EMU00042", list[0].serial);
  EXPECT_EQ(14, list[0].firmware);
  EXPECT_EQ(3, list[0].bus);
  EXPECT_EQ(7, list[0].address);
}

TEST(Dvs128DeviceUmockdev, MissingSerialListsVisibleCamerasAndUdevRule)
{
  Dvs128Emulator emu("EMU00042", 14);
  CheckingListener l;
  dvs_driver::Dvs128DeviceOptions o;
  o.serial = "NOPE";
  dvs_driver::Dvs128Device dev(o, l);
  try
  {
    dev.open();
    FAIL() << "opened a camera with the wrong serial";
  }
  catch (const dvs_driver::Dvs128DeviceError& e)
  {
    const std::string m = e.what();
    EXPECT_NE(std::string::npos, m.find("serial `NOPE`")) << m;
    EXPECT_NE(std::string::npos, m.find("serial EMU00042")) << m;
    EXPECT_NE(std::string::npos, m.find("88-dvs128.rules")) << m;
  }
}

TEST(Dvs128DeviceUmockdev, OldFirmwareIsRefused)
{
  Dvs128Emulator emu("OLD", 9);
  CheckingListener l;
  dvs_driver::Dvs128Device dev(dvs_driver::Dvs128DeviceOptions(), l);
  try
  {
    dev.open();
    FAIL() << "accepted firmware 9";
  }
  catch (const dvs_driver::Dvs128DeviceError& e)
  {
    EXPECT_NE(std::string::npos, std::string(e.what()).find("firmware 9")) << e.what();
  }
}

TEST(Dvs128DeviceUmockdev, ControlSequenceBiasBytesAndStreaming)
{
  Dvs128Emulator emu("EMU00042", 14);
  emu.setEventRate(200000);
  CheckingListener l;
  dvs_driver::Dvs128DeviceOptions o;
  o.serial = "EMU00042";
  dvs_driver::Dvs128Device dev(o, l);
  dev.start();
  ASSERT_TRUE(waitFor([&] { return l.events.load() >= 20000; })) << "events: " << l.events.load();

  // Exact control sequence of a start: biases, master, start, timestamp reset.
  const auto c = emu.controls();
  ASSERT_EQ((std::vector<uint8_t>{0xB8, 0xBE, 0xB3, 0xBB}), vendorRequests(c));
  for (const auto& x : c)
  {
    EXPECT_EQ(0x40, x.request_type);
    EXPECT_EQ(0, x.index);
  }
  // Fast biases, 24-bit big-endian: cas 1992 = 00 07 C8, injGnd 1108364 = 10 E9 8C, ...
  const std::vector<uint8_t> fast = {0x00, 0x07, 0xC8, 0x10, 0xE9, 0x8C, 0xFF, 0xFF, 0xFF, 0x7C, 0x7F, 0xF5,
                                     0x00, 0x00, 0x84, 0x04, 0xB9, 0x56, 0x00, 0x03, 0xC9, 0xFF, 0xFF, 0xFF,
                                     0x03, 0x34, 0x4C, 0x00, 0x33, 0x45, 0x00, 0x01, 0x0F, 0x00, 0x00, 0xD9};
  EXPECT_EQ(fast, c[0].data);
  EXPECT_EQ(1, c[1].value);  // master
  EXPECT_EQ(1, l.resets_sent.load());
  EXPECT_EQ(1u, l.decoder.stats().resets);

  // Changing one bias sends all 36 bytes again with just that bias changed.
  emu.clearControls();
  dev.setBias("diffOn", 0x123456);
  dev.setMaster(false);
  dev.resetArray();
  const auto c2 = emu.controls();
  ASSERT_EQ((std::vector<uint8_t>{0xB8, 0xBE, 0xBD}), vendorRequests(c2));
  std::vector<uint8_t> changed = fast;
  changed[24] = 0x12;
  changed[25] = 0x34;
  changed[26] = 0x56;
  EXPECT_EQ(changed, c2[0].data);
  EXPECT_EQ(0, c2[1].value);  // slave

  dev.stop();
  EXPECT_EQ(0xB4, emu.controls().back().request);  // stop sent on shutdown
  EXPECT_EQ(0u, l.out_of_order.load());
  EXPECT_EQ(0u, l.decoder.stats().non_monotonic);
  EXPECT_GE(emu.eventsSent(), l.events.load());
}

TEST(Dvs128DeviceUmockdev, UnplugReplugResumesWithSameSettings)
{
  Dvs128Emulator emu("EMU00042", 14);
  emu.setEventRate(100000);
  CheckingListener l;
  dvs_driver::Dvs128DeviceOptions o;
  o.reconnect_interval_s = 0.05;
  dvs_driver::Dvs128Device dev(o, l);
  dev.start();
  ASSERT_TRUE(waitFor([&] { return l.events.load() >= 5000; }));
  dev.setBias("refr", 77);

  emu.unplug();
  ASSERT_TRUE(waitFor([&] { return l.disconnects.load() == 1; })) << "unplug not noticed";
  EXPECT_FALSE(dev.connected());
  {
    std::lock_guard<std::mutex> lock(l.mutex);
    EXPECT_NE(std::string::npos, l.last_disconnect.find("EMU00042")) << l.last_disconnect;
  }
  std::this_thread::sleep_for(200ms);  // several failed reopen attempts
  const uint64_t before = l.events.load();
  emu.clearControls();

  emu.plug();
  ASSERT_TRUE(waitFor([&] { return l.connects.load() == 2; })) << "no reconnect";
  ASSERT_TRUE(waitFor([&] { return l.events.load() >= before + 5000; })) << "no events after replug";
  EXPECT_TRUE(dev.connected());
  EXPECT_EQ(1u, dev.stats().reconnects);
  EXPECT_EQ(1u, dev.stats().disconnects);

  // Same settings again: the changed bias, master, start, reset.
  const auto c = emu.controls();
  ASSERT_GE(c.size(), 4u);
  const std::vector<uint8_t> requests = vendorRequests(c);
  EXPECT_EQ((std::vector<uint8_t>{0xB8, 0xBE, 0xB3, 0xBB}), std::vector<uint8_t>(requests.begin(), requests.begin() + 4));
  EXPECT_EQ(0x00, c[0].data[18]);
  EXPECT_EQ(0x00, c[0].data[19]);
  EXPECT_EQ(77, c[0].data[20]);
  dev.stop();
  EXPECT_EQ(2u, l.decoder.stats().resets);  // one reset marker per (re)start
  EXPECT_EQ(0u, l.out_of_order.load());     // no event lost or reordered across the replug
}

int main(int argc, char** argv)
{
  dvs_driver_test::reexecUnderUmockdev(argc, argv);
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
