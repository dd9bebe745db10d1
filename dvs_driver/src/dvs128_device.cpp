#include <dvs_driver/dvs128_device.h>

#include <libusb-1.0/libusb.h>

#include <chrono>
#include <sstream>

namespace dvs_driver
{
const char* const kDvs128UdevHint =
    "If the camera is plugged in but not listed or cannot be opened, install the udev rule shipped with "
    "dvs_driver: sudo cp $(rospack find dvs_driver)/udev/88-dvs128.rules /etc/udev/rules.d/ && "
    "sudo udevadm control --reload-rules && sudo udevadm trigger, then re-plug the camera.";

struct Dvs128Device::Transfer
{
  Dvs128Device* owner = nullptr;
  libusb_transfer* transfer = nullptr;
  std::vector<uint8_t> buffer;
};

namespace
{
std::string usbError(int r)
{
  return std::string(libusb_error_name(r)) + " (" + libusb_strerror(static_cast<libusb_error>(r)) + ")";
}
}  // namespace

Dvs128Device::Dvs128Device(const Dvs128DeviceOptions& options, Dvs128Listener& listener)
  : options_(options), listener_(listener)
{
  if (options_.transfers < 1 || options_.transfers > 64)
    throw Dvs128DeviceError("transfers must be in [1, 64], got " + std::to_string(options_.transfers));
  if (options_.transfer_size < 512 || options_.transfer_size % 512 != 0 || options_.transfer_size > (1 << 20))
    throw Dvs128DeviceError("transfer_size must be a multiple of 512 in [512, 1 MiB], got " +
                            std::to_string(options_.transfer_size));
  const int r = libusb_init(&ctx_);
  if (r != 0)
    throw Dvs128DeviceError("libusb_init failed: " + usbError(r));
}

Dvs128Device::~Dvs128Device()
{
  stop();
  libusb_exit(ctx_);
}

std::vector<Dvs128DeviceInfo> Dvs128Device::listDevices()
{
  std::vector<Dvs128DeviceInfo> out;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx_, &list);
  for (ssize_t i = 0; i < n; ++i)
  {
    libusb_device_descriptor desc;
    if (libusb_get_device_descriptor(list[i], &desc) != 0 || desc.idVendor != kDvs128VendorId ||
        desc.idProduct != kDvs128ProductId)
      continue;
    Dvs128DeviceInfo info;
    info.bus = libusb_get_bus_number(list[i]);
    info.address = libusb_get_device_address(list[i]);
    info.firmware = desc.bcdDevice & 0xFF;
    libusb_device_handle* h = nullptr;
    const int r = libusb_open(list[i], &h);
    if (r != 0)
      info.error = "cannot open: " + usbError(r);
    else
    {
      unsigned char serial[256] = {0};
      if (desc.iSerialNumber != 0)
      {
        const int len = libusb_get_string_descriptor_ascii(h, desc.iSerialNumber, serial, sizeof(serial) - 1);
        if (len > 0)
          info.serial.assign(reinterpret_cast<char*>(serial), static_cast<size_t>(len));
        else
          info.error = "cannot read serial: " + usbError(len);
      }
      libusb_close(h);
    }
    out.push_back(info);
  }
  if (n > 0)
    libusb_free_device_list(list, 1);
  return out;
}

std::string Dvs128Device::describeVisibleDevices()
{
  const auto devices = listDevices();
  std::ostringstream os;
  if (devices.empty())
    os << "no DVS128 (USB 152a:8400) is visible. ";
  else
  {
    os << "visible DVS128 cameras:";
    for (const auto& d : devices)
    {
      os << " [serial " << (d.serial.empty() ? "?" : d.serial) << ", bus " << int(d.bus) << " address "
         << int(d.address) << ", firmware " << d.firmware;
      if (!d.error.empty())
        os << ", " << d.error;
      os << "]";
    }
    os << ". ";
  }
  os << kDvs128UdevHint;
  return os.str();
}

bool Dvs128Device::tryOpen(std::string& why)
{
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx_, &list);
  if (n < 0)
  {
    why = "libusb_get_device_list failed: " + usbError(static_cast<int>(n));
    return false;
  }
  std::string serial_wanted;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    serial_wanted = options_.serial;
  }
  why = serial_wanted.empty() ? "no DVS128 found" : "no DVS128 with serial `" + serial_wanted + "` found";
  libusb_device_handle* h = nullptr;
  Dvs128DeviceInfo info;
  for (ssize_t i = 0; i < n && !h; ++i)
  {
    libusb_device_descriptor desc;
    if (libusb_get_device_descriptor(list[i], &desc) != 0 || desc.idVendor != kDvs128VendorId ||
        desc.idProduct != kDvs128ProductId)
      continue;
    int r = libusb_open(list[i], &h);
    if (r != 0)
    {
      why = "cannot open DVS128 on bus " + std::to_string(libusb_get_bus_number(list[i])) + ": " + usbError(r);
      h = nullptr;
      continue;
    }
    info = Dvs128DeviceInfo();
    info.bus = libusb_get_bus_number(list[i]);
    info.address = libusb_get_device_address(list[i]);
    info.firmware = desc.bcdDevice & 0xFF;
    unsigned char serial[256] = {0};
    if (desc.iSerialNumber != 0)
    {
      r = libusb_get_string_descriptor_ascii(h, desc.iSerialNumber, serial, sizeof(serial) - 1);
      if (r > 0)
        info.serial.assign(reinterpret_cast<char*>(serial), static_cast<size_t>(r));
    }
    if (!serial_wanted.empty() && info.serial != serial_wanted)
    {
      libusb_close(h);
      h = nullptr;
      continue;
    }
    if (info.firmware < options_.min_firmware)
    {
      why = "DVS128 " + info.serial + " has firmware " + std::to_string(info.firmware) + ", at least " +
            std::to_string(options_.min_firmware) + " is required (update it with jAER)";
      libusb_close(h);
      h = nullptr;
      continue;
    }
    int config = 0;
    r = libusb_get_configuration(h, &config);
    if (r == 0 && config != 1)
      r = libusb_set_configuration(h, 1);
    if (r != 0)
    {
      why = "cannot select configuration 1 of DVS128 " + info.serial + ": " + usbError(r);
      libusb_close(h);
      h = nullptr;
      continue;
    }
    r = libusb_claim_interface(h, 0);
    if (r != 0)
    {
      why = "cannot claim interface 0 of DVS128 " + info.serial + ": " + usbError(r) +
            (r == LIBUSB_ERROR_BUSY ? " (another program uses the camera)" : "");
      libusb_close(h);
      h = nullptr;
      continue;
    }
  }
  libusb_free_device_list(list, 1);
  if (!h)
    return false;
  if (info.firmware < 14)
    listener_.onWarning("DVS128 " + info.serial + " has firmware " + std::to_string(info.firmware) +
                        " (libcaer expects 14)");
  std::lock_guard<std::mutex> lock(mutex_);
  handle_ = h;
  info_ = info;
  // Reconnect to this very camera, not to whichever is first.
  if (options_.serial.empty())
    options_.serial = info.serial;
  return true;
}

void Dvs128Device::open()
{
  if (handle_)
    return;
  std::string why;
  if (!tryOpen(why))
    throw Dvs128DeviceError(why + "; " + describeVisibleDevices());
}

bool Dvs128Device::control(uint8_t request, uint16_t value, const uint8_t* data, uint16_t size, std::string* why)
{
  int r;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!handle_)
    {
      if (why)
        *why = "camera not connected";
      return false;
    }
    r = libusb_control_transfer(handle_, LIBUSB_REQUEST_TYPE_VENDOR | LIBUSB_RECIPIENT_DEVICE | LIBUSB_ENDPOINT_OUT,
                                request, value, 0, const_cast<uint8_t*>(data), size,
                                static_cast<unsigned>(options_.control_timeout_ms));
  }
  if (r < 0)
  {
    char hex[8];
    std::snprintf(hex, sizeof(hex), "0x%02X", request);
    const std::string msg = std::string("control request ") + hex + " failed: " + usbError(r);
    if (why)
      *why = msg;
    listener_.onWarning(msg);  // outside the lock: the listener may call back into the device
    return false;
  }
  return true;
}

void Dvs128Device::configure()
{
  Dvs128Biases biases;
  bool master;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    biases = options_.biases;
    master = options_.master;
  }
  const auto bytes = encodeBiases(biases);
  control(kDvs128SetBiases, 0, bytes.data(), static_cast<uint16_t>(bytes.size()));
  control(kDvs128TimestampMaster, master ? 1 : 0, nullptr, 0);
  control(kDvs128Start, 0, nullptr, 0);
  if (options_.reset_timestamps_on_start && master)
    resetTimestamps();
}

void Dvs128Device::submitTransfers()
{
  if (transfers_.empty())
  {
    for (int i = 0; i < options_.transfers; ++i)
    {
      auto t = std::make_unique<Transfer>();
      t->owner = this;
      t->buffer.resize(static_cast<size_t>(options_.transfer_size));
      t->transfer = libusb_alloc_transfer(0);
      transfers_.push_back(std::move(t));
    }
  }
  for (auto& t : transfers_)
  {
    libusb_fill_bulk_transfer(t->transfer, handle_, kDvs128DataEndpoint, t->buffer.data(),
                              static_cast<int>(t->buffer.size()), &Dvs128Device::transferCallback, t.get(), 0);
    const int r = libusb_submit_transfer(t->transfer);
    if (r == 0)
      ++active_transfers_;
    else
    {
      ++transfer_errors_;
      listener_.onWarning("cannot submit bulk transfer: " + usbError(r));
      if (r == LIBUSB_ERROR_NO_DEVICE)
        lost_ = true;
    }
  }
}

void Dvs128Device::transferCallback(libusb_transfer* t)
{
  Transfer* tr = static_cast<Transfer*>(t->user_data);
  tr->owner->onTransfer(*tr);
}

void Dvs128Device::onTransfer(Transfer& tr)
{
  libusb_transfer* t = tr.transfer;
  switch (t->status)
  {
    case LIBUSB_TRANSFER_COMPLETED:
      if (t->actual_length > 0)
      {
        listener_.onData(t->buffer, static_cast<size_t>(t->actual_length));
        bytes_ += static_cast<uint64_t>(t->actual_length);
      }
      ++transfers_done_;
      break;
    case LIBUSB_TRANSFER_CANCELLED:
      --active_transfers_;
      return;
    case LIBUSB_TRANSFER_NO_DEVICE:
      lost_ = true;
      --active_transfers_;
      return;
    default:  // error, stall, overflow, timeout: count and keep going
      ++transfer_errors_;
      break;
  }
  if (stopping_ || lost_)
  {
    --active_transfers_;
    return;
  }
  const int r = libusb_submit_transfer(t);
  if (r != 0)
  {
    --active_transfers_;
    ++transfer_errors_;
    if (r == LIBUSB_ERROR_NO_DEVICE)
      lost_ = true;
  }
}

void Dvs128Device::handleUntilIdle()
{
  // Cancel what is in flight and let the callbacks run until nothing is left.
  for (auto& t : transfers_)
    libusb_cancel_transfer(t->transfer);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (active_transfers_ > 0 && std::chrono::steady_clock::now() < deadline)
  {
    timeval tv{0, 50000};
    libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
  }
}

void Dvs128Device::closeHandle()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!handle_)
      return;
    libusb_release_interface(handle_, 0);
    libusb_close(handle_);  // also forgets transfers a vanished device never completed
    handle_ = nullptr;
  }
  if (active_transfers_ != 0)
  {
    // Those transfers were dropped by libusb_close: free them, submitTransfers() makes new ones.
    for (auto& t : transfers_)
      libusb_free_transfer(t->transfer);
    transfers_.clear();
    active_transfers_ = 0;
  }
}

void Dvs128Device::start()
{
  if (thread_.joinable())
    return;
  open();
  stopping_ = false;
  thread_ = std::thread(&Dvs128Device::run, this);
}

void Dvs128Device::run()
{
  bool fresh = true;  // the handle opened by open() is not yet configured
  while (!stopping_)
  {
    if (!handle_)
    {
      std::string why;
      if (!tryOpen(why))
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait_for(lock, std::chrono::duration<double>(options_.reconnect_interval_s),
                       [this] { return stopping_.load(); });
        continue;
      }
      ++reconnects_;
      fresh = true;
    }
    if (fresh)
    {
      lost_ = false;
      submitTransfers();
      configure();
      fresh = false;
      if (!lost_)
      {
        connected_ = true;
        listener_.onConnected(info());
      }
    }
    timeval tv{0, 100000};
    libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
    if (lost_)
    {
      connected_ = false;
      ++disconnects_;
      handleUntilIdle();
      closeHandle();
      listener_.onDisconnected("DVS128 " + info().serial + " disconnected; trying to reopen it every " +
                               std::to_string(options_.reconnect_interval_s) + " s");
    }
  }
  // Orderly stop.
  if (handle_ && !lost_)
    control(kDvs128Stop, 0, nullptr, 0);
  handleUntilIdle();
  closeHandle();
  connected_ = false;
}

void Dvs128Device::stop()
{
  stopping_ = true;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    wake_.notify_all();
  }
  if (thread_.joinable())
    thread_.join();
  else
    closeHandle();
  for (auto& t : transfers_)
    libusb_free_transfer(t->transfer);
  transfers_.clear();
}

void Dvs128Device::setBiases(const Dvs128Biases& biases)
{
  for (uint32_t v : biases.values)
    if (v > kDvs128BiasMax)
      throw BiasError("bias value " + std::to_string(v) + " exceeds 16777215 (24 bits)");
  {
    std::lock_guard<std::mutex> lock(mutex_);
    options_.biases = biases;
  }
  const auto bytes = encodeBiases(biases);
  if (connected_)
    control(kDvs128SetBiases, 0, bytes.data(), static_cast<uint16_t>(bytes.size()));
}

void Dvs128Device::setBias(const std::string& name, uint32_t value)
{
  Dvs128Biases b = biases();
  b.set(name, value);
  setBiases(b);
}

Dvs128Biases Dvs128Device::biases() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return options_.biases;
}

void Dvs128Device::resetTimestamps()
{
  // Announce first: the reset marker can come back (on another thread) before control() returns.
  listener_.onTimestampResetRequest();
  control(kDvs128ResetTimestamps, 0, nullptr, 0);
}

void Dvs128Device::setMaster(bool master)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    options_.master = master;
  }
  control(kDvs128TimestampMaster, master ? 1 : 0, nullptr, 0);
}

void Dvs128Device::resetArray()
{
  control(kDvs128ArrayReset, 0, nullptr, 0);
}

Dvs128DeviceInfo Dvs128Device::info() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return info_;
}

Dvs128DeviceStats Dvs128Device::stats() const
{
  Dvs128DeviceStats s;
  s.bytes = bytes_;
  s.transfers = transfers_done_;
  s.transfer_errors = transfer_errors_;
  s.reconnects = reconnects_;
  s.disconnects = disconnects_;
  return s;
}
}  // namespace dvs_driver
