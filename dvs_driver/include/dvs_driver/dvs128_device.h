#pragma once
// DVS128 over libusb (ROS-free). Enumerates cameras (152a:8400), opens one by serial, checks the
// firmware, selects configuration 1, claims interface 0, keeps N asynchronous bulk IN transfers
// on endpoint 0x86 in flight on a dedicated thread, and sends the vendor control requests
// (start/stop, biases, timestamp reset, master/slave, array reset). An unplugged camera is
// reported, re-opened by the same serial every reconnect interval, and re-configured with the
// same settings. Data and state changes reach the owner through Dvs128Listener.
#include <dvs_driver/dvs128_biases.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

struct libusb_context;
struct libusb_device_handle;
struct libusb_transfer;

namespace dvs_driver
{
constexpr uint16_t kDvs128VendorId = 0x152A;
constexpr uint16_t kDvs128ProductId = 0x8400;
constexpr uint8_t kDvs128DataEndpoint = 0x86;

/// Vendor requests (bmRequestType 0x40).
enum Dvs128Request : uint8_t
{
  kDvs128Start = 0xB3,
  kDvs128Stop = 0xB4,
  kDvs128SetBiases = 0xB8,
  kDvs128ResetTimestamps = 0xBB,
  kDvs128ArrayResetHold = 0xBC,
  kDvs128ArrayReset = 0xBD,
  kDvs128TimestampMaster = 0xBE,
};

/// Where the udev rule lives in the source tree and how to install it (used in messages).
extern const char* const kDvs128UdevHint;

/// Thrown when no (matching) camera can be opened; the message lists the cameras visible.
class Dvs128DeviceError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

struct Dvs128DeviceInfo
{
  std::string serial;       ///< iSerialNumber ("" when it could not be read)
  uint8_t bus = 0;
  uint8_t address = 0;
  uint16_t firmware = 0;    ///< low byte of bcdDevice
  std::string error;        ///< why it could not be opened to read the serial, if so
};

/// Callbacks from the device thread. Keep them short: they run between transfer completions.
class Dvs128Listener
{
public:
  virtual ~Dvs128Listener() = default;
  /// One completed bulk IN transfer (raw event words; may end mid-word).
  virtual void onData(const uint8_t* data, size_t size) = 0;
  /// The camera is open, configured and streaming (first time and after every reconnect).
  virtual void onConnected(const Dvs128DeviceInfo&) {}
  /// The camera went away or failed; the device keeps trying to reopen it.
  virtual void onDisconnected(const std::string& /*why*/) {}
  /// A timestamp reset request (0xBB) is about to be sent; the device answers with a reset
  /// marker in the stream, possibly before the request call returns.
  virtual void onTimestampResetRequest() {}
  virtual void onWarning(const std::string& /*message*/) {}
};

struct Dvs128DeviceOptions
{
  std::string serial;                  ///< "" = first camera found
  int transfers = 8;                   ///< bulk transfers kept in flight
  int transfer_size = 4096;            ///< bytes per transfer (multiple of 512)
  bool master = true;                  ///< timestamp master (true) or slave (false)
  Dvs128Biases biases = fastBiases();
  double reconnect_interval_s = 0.5;   ///< between reopen attempts after an unplug
  int min_firmware = 11;               ///< refuse older firmware (jAER warns below 11)
  bool reset_timestamps_on_start = true;
  int control_timeout_ms = 1000;
};

struct Dvs128DeviceStats
{
  uint64_t bytes = 0;
  uint64_t transfers = 0;         ///< completed bulk transfers
  uint64_t transfer_errors = 0;   ///< failed/stalled/overflowed transfers
  uint64_t reconnects = 0;        ///< successful reopen after a disconnect
  uint64_t disconnects = 0;
};

class Dvs128Device
{
public:
  Dvs128Device(const Dvs128DeviceOptions& options, Dvs128Listener& listener);
  ~Dvs128Device();
  Dvs128Device(const Dvs128Device&) = delete;
  Dvs128Device& operator=(const Dvs128Device&) = delete;

  /// Cameras visible on the bus (serials read where the device can be opened).
  std::vector<Dvs128DeviceInfo> listDevices();
  /// Human-readable list of visible cameras plus the udev hint (for error messages).
  std::string describeVisibleDevices();

  /// Open and configure the requested camera. Throws Dvs128DeviceError with the list of visible
  /// cameras and the udev hint when it is missing or cannot be opened.
  void open();
  /// Start streaming on the device thread (open() first). Returns immediately.
  void start();
  /// Stop streaming, join the thread, close the device. Safe to call twice.
  void stop();

  /// Set all biases / one bias: sent now when connected, and again after every reconnect.
  void setBiases(const Dvs128Biases& biases);
  void setBias(const std::string& name, uint32_t value);
  Dvs128Biases biases() const;
  /// Request a timestamp reset (the device emits a reset marker in the stream).
  void resetTimestamps();
  void setMaster(bool master);
  /// One-shot pixel array reset.
  void resetArray();

  bool connected() const { return connected_.load(); }
  Dvs128DeviceInfo info() const;
  Dvs128DeviceStats stats() const;

private:
  struct Transfer;
  static void transferCallback(libusb_transfer* t);
  void onTransfer(Transfer& t);
  bool tryOpen(std::string& why);   // opens options_.serial (or the first); false + why on failure
  void configure();                 // biases, master/slave, start, reset
  bool control(uint8_t request, uint16_t value, const uint8_t* data, uint16_t size, std::string* why = nullptr);
  void submitTransfers();
  void closeHandle();
  void run();
  void handleUntilIdle();

  Dvs128DeviceOptions options_;
  Dvs128Listener& listener_;
  libusb_context* ctx_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  mutable std::mutex mutex_;  // options_ (biases, master), info_, handle_ for control requests
  Dvs128DeviceInfo info_;
  std::vector<std::unique_ptr<Transfer>> transfers_;
  std::atomic<int> active_transfers_{0};
  std::atomic<bool> stopping_{false};
  std::atomic<bool> connected_{false};
  std::atomic<bool> lost_{false};
  std::thread thread_;
  std::condition_variable wake_;

  std::atomic<uint64_t> bytes_{0}, transfers_done_{0}, transfer_errors_{0}, reconnects_{0}, disconnects_{0};
};
}  // namespace dvs_driver
