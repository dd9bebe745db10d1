#pragma once
// The live DVS128 as an EventInput: Dvs128Device (libusb) + Dvs128Decoder. Each completed
// transfer is decoded (words split across transfers are joined) into a reused buffer and handed
// to the listener as one chunk.
#include <dvs_driver/dvs128_decoder.h>
#include <dvs_driver/dvs128_device.h>
#include <dvs_driver/event_input.h>

#include <atomic>
#include <memory>
#include <thread>

namespace dvs_driver
{
struct DeviceInputStats
{
  Dvs128DeviceStats device;
  Dvs128DecoderStats decoder;
};

class DeviceInput : public EventInput, private Dvs128Listener
{
public:
  explicit DeviceInput(const Dvs128DeviceOptions& options);
  ~DeviceInput() override;

  /// Opens the camera (retrying every reconnect interval until it appears or stop() is called;
  /// the first failure is reported through onWarning with the list of visible cameras) and
  /// streams. Returns immediately.
  void start(EventInputListener& listener) override;
  void stop() override;
  std::string description() const override;

  Dvs128Device& device() { return *device_; }
  DeviceInputStats stats() const;

private:
  void onData(const uint8_t* data, size_t size) override;
  void onConnected(const Dvs128DeviceInfo& info) override;
  void onDisconnected(const std::string& why) override;
  void onTimestampResetRequest() override;
  void onWarning(const std::string& message) override;

  struct Collector;
  Dvs128DeviceOptions options_;
  std::unique_ptr<Dvs128Device> device_;
  Dvs128Decoder decoder_;
  EventVector chunk_;
  EventInputListener* listener_ = nullptr;
  std::thread opener_;
  std::atomic<bool> stopping_{false};
  mutable std::mutex stats_mutex_;
  Dvs128DecoderStats decoder_stats_;
};
}  // namespace dvs_driver
