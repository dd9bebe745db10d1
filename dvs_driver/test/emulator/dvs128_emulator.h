#pragma once
// An emulated DVS128 for tests and benchmarks of the real libusb code path (umockdev).
// A UMockdevTestbed holds a USB device with the DVS128's descriptors (152a:8400, firmware 14,
// serial string, one bulk IN endpoint 0x86); a UMockdevIoctlBase answers the usbdevfs ioctls
// libusb issues on its device node: control URBs (string descriptors, the vendor requests,
// which are recorded), bulk IN URBs (filled with generated event words at a set rate in real
// time) and their reaping, discards, capabilities. unplug() makes every ioctl fail with ENODEV
// and removes the device; plug() adds it back.
//
// The process must run with libumockdev-preload (umockdev-wrapper); reexecUnderUmockdev()
// restarts the current program that way when needed.
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dvs_driver_test
{
/// One vendor control request the emulated camera received.
struct ControlRecord
{
  uint8_t request_type;
  uint8_t request;
  uint16_t value;
  uint16_t index;
  std::vector<uint8_t> data;
};

/// Raw (unflipped) address of generated event k: raw x = k % 128, raw y = (k / 128) % 128,
/// OFF when (k / 16384) is odd. Device time of event k: k * 1e6 / rate us after streaming start.
uint16_t generatedAddress(uint64_t k);

class Dvs128Emulator
{
public:
  explicit Dvs128Emulator(const std::string& serial = "EMU00042", uint16_t firmware = 14);
  ~Dvs128Emulator();

  /// Add the device (again) to the testbed.
  void plug();
  /// Emulated unplug: in-flight and new requests fail with ENODEV, the device leaves the testbed.
  void unplug();
  bool plugged() const;

  /// Event rate of the generator (events/s of device time = wall time). Default 100,000.
  void setEventRate(double events_per_second);
  /// Complete a bulk URB at least this often when events are pending (us). Default 500.
  void setFlushIntervalUs(int us);
  /// Stop generating after this many events (0 = unlimited).
  void setEventLimit(uint64_t n);

  std::vector<ControlRecord> controls() const;
  void clearControls();
  /// Pixel events handed to the host so far (since construction).
  uint64_t eventsSent() const;
  /// Bulk IN URBs completed with data.
  uint64_t urbsCompleted() const;
  bool streaming() const;

  /// One completed bulk URB: events [0, events_end) had been sent when it completed at `time`.
  struct Completion
  {
    uint64_t events_end;
    std::chrono::steady_clock::time_point time;
  };
  /// Record every bulk completion (for latency benchmarks); off by default.
  void recordCompletions(bool on);
  std::vector<Completion> completions() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// If libumockdev-preload is not loaded, exec `umockdev-wrapper argv...` (does not return on
/// success). Call first thing in main().
void reexecUnderUmockdev(int argc, char** argv);
}  // namespace dvs_driver_test
