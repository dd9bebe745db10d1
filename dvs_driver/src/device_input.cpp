#include <dvs_driver/device_input.h>

#include <chrono>

namespace dvs_driver
{
// Decoder consumer: pixel events into the chunk, resets to the listener.
struct DeviceInput::Collector : Dvs128ConsumerBase
{
  EventVector& out;
  EventInputListener& listener;
  Collector(EventVector& o, EventInputListener& l) : out(o), listener(l) {}
  void event(int64_t t_us, uint16_t x, uint16_t y, bool polarity)
  {
    out.push_back(Event{t_us * 1000, x, y, polarity});
  }
  void timestampReset()
  {
    // Events before the marker belong to the old time base: deliver them first.
    if (!out.empty())
    {
      listener.onEvents(out.data(), out.data() + out.size());
      out.clear();
    }
    listener.onTimestampReset();
  }
};

DeviceInput::DeviceInput(const Dvs128DeviceOptions& options)
  : options_(options), device_(new Dvs128Device(options, *this))
{
  chunk_.reserve(static_cast<size_t>(options.transfer_size) / 4 + 1);
}

DeviceInput::~DeviceInput()
{
  stop();
}

std::string DeviceInput::description() const
{
  return "DVS128 " + (options_.serial.empty() ? std::string("(first found)") : options_.serial);
}

void DeviceInput::start(EventInputListener& listener)
{
  listener_ = &listener;
  stopping_ = false;
  opener_ = std::thread([this] {
    bool reported = false;
    while (!stopping_)
    {
      try
      {
        device_->start();
        return;
      }
      catch (const Dvs128DeviceError& e)
      {
        if (!reported)
          listener_->onStatus(false, std::string("cannot open the camera: ") + e.what() + " Retrying every " +
                                         std::to_string(options_.reconnect_interval_s) + " s.");
        reported = true;
      }
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(options_.reconnect_interval_s);
      while (!stopping_ && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
}

void DeviceInput::stop()
{
  stopping_ = true;
  if (opener_.joinable())
    opener_.join();
  device_->stop();
}

void DeviceInput::onData(const uint8_t* data, size_t size)
{
  chunk_.clear();
  Collector c(chunk_, *listener_);
  decoder_.decode(data, size, c);
  if (!chunk_.empty())
    listener_->onEvents(chunk_.data(), chunk_.data() + chunk_.size());
  std::lock_guard<std::mutex> lock(stats_mutex_);
  decoder_stats_ = decoder_.stats();
}

void DeviceInput::onConnected(const Dvs128DeviceInfo& info)
{
  decoder_.reset();  // a partial word from before an unplug is garbage now
  listener_->onStatus(true, "DVS128 " + info.serial + " (firmware " + std::to_string(info.firmware) + ") streaming");
}

void DeviceInput::onDisconnected(const std::string& why)
{
  listener_->onStatus(false, why);
}

void DeviceInput::onTimestampResetRequest()
{
  listener_->onTimestampResetRequest();
}

void DeviceInput::onWarning(const std::string& message)
{
  listener_->onWarning(message);
}

DeviceInputStats DeviceInput::stats() const
{
  DeviceInputStats s;
  s.device = device_->stats();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  s.decoder = decoder_stats_;
  return s;
}
}  // namespace dvs_driver
