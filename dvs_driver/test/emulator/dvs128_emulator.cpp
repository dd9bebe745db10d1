#include "dvs128_emulator.h"

#include <umockdev.h>

#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <mutex>
#include <unistd.h>

namespace dvs_driver_test
{
namespace
{
using Clock = std::chrono::steady_clock;
const char* kSysPath = "/sys/devices/pci0000:00/0000:00:14.0/usb3/3-1";
const char* kDevNode = "/dev/bus/usb/003/007";

std::string hex(const std::vector<uint8_t>& b)
{
  std::string s;
  char buf[3];
  for (uint8_t v : b)
  {
    std::snprintf(buf, sizeof(buf), "%02x", v);
    s += buf;
  }
  return s;
}

std::vector<uint8_t> stringDescriptor(const std::string& s)
{
  std::vector<uint8_t> d = {static_cast<uint8_t>(2 + 2 * s.size()), 0x03};
  for (char c : s)
  {
    d.push_back(static_cast<uint8_t>(c));
    d.push_back(0);
  }
  return d;
}
}  // namespace

uint16_t generatedAddress(uint64_t k)
{
  const uint16_t raw_x = static_cast<uint16_t>(k % 128);
  const uint16_t raw_y = static_cast<uint16_t>((k / 128) % 128);
  const uint16_t off = static_cast<uint16_t>((k / 16384) % 2);
  return static_cast<uint16_t>((raw_y << 8) | (raw_x << 1) | off);
}

struct Dvs128Emulator::Impl
{
  std::string serial;
  uint16_t firmware;
  UMockdevTestbed* testbed = nullptr;
  UMockdevIoctlBase* handler = nullptr;
  gulong signal_id = 0;
  bool attached = false;

  mutable std::mutex mutex;
  bool plugged = false;
  bool streaming = false;
  double rate = 100000.0;
  int flush_us = 500;
  uint64_t limit = 0;
  std::vector<ControlRecord> controls;
  std::deque<UMockdevIoctlData*> bulk_in;     // submitted IN URBs, oldest first
  std::deque<UMockdevIoctlData*> ready;       // completed control URBs waiting to be reaped
  std::deque<UMockdevIoctlData*> discarded;   // discarded URBs waiting to be reaped
  std::deque<UMockdevIoctlData*> dead;        // URBs in flight at the unplug
  // Generator.
  Clock::time_point start_time;
  uint64_t next_event = 0;            // index of the next event to send
  int64_t reset_at_us = 0;            // generator time of the last timestamp reset
  int64_t last_word_dev_us = 0;       // device time of the last word sent (for wraps)
  bool reset_pending = false;
  Clock::time_point last_flush;
  uint64_t events_sent = 0;
  uint64_t urbs_completed = 0;
  bool record = false;
  std::vector<Completion> completions;

  static gboolean onIoctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer self)
  {
    return static_cast<Impl*>(self)->handle(client) ? TRUE : FALSE;
  }

  int64_t eventTimeUs(uint64_t k) const { return static_cast<int64_t>(static_cast<double>(k) * 1e6 / rate); }

  // Fill words of events due by `now` into buf (capacity bytes). Returns bytes written.
  size_t generate(uint8_t* buf, size_t capacity, Clock::time_point now)
  {
    size_t n = 0;
    auto put = [&](uint8_t b0, uint8_t b1, uint8_t b2, uint8_t b3) {
      buf[n] = b0;
      buf[n + 1] = b1;
      buf[n + 2] = b2;
      buf[n + 3] = b3;
      n += 4;
    };
    if (reset_pending && capacity >= 4)
    {
      put(0, 0, 0, 0x40);
      reset_pending = false;
      last_word_dev_us = 0;
    }
    const int64_t elapsed_us = std::chrono::duration_cast<std::chrono::microseconds>(now - start_time).count();
    while (n + 8 <= capacity)  // room for a wrap and an event
    {
      if (limit && next_event >= limit)
        break;
      const int64_t t = eventTimeUs(next_event);
      if (t > elapsed_us)
        break;
      int64_t dev = t - reset_at_us;
      if (dev < 0)
        dev = 0;
      if (dev / 16384 > last_word_dev_us / 16384)
      {
        put(0, 0, 0, 0x80);  // one wrap per 16384 us boundary crossed
        last_word_dev_us = (last_word_dev_us / 16384 + 1) * 16384;
        continue;
      }
      const uint16_t addr = generatedAddress(next_event);
      const uint16_t ts = static_cast<uint16_t>(dev % 16384);
      put(static_cast<uint8_t>(addr & 0xFF), static_cast<uint8_t>(addr >> 8), static_cast<uint8_t>(ts & 0xFF),
          static_cast<uint8_t>(ts >> 8));
      last_word_dev_us = dev;
      ++next_event;
      ++events_sent;
    }
    return n;
  }

  bool eventsDue(Clock::time_point now) const
  {
    if (!streaming || (limit && next_event >= limit))
      return reset_pending;
    const int64_t elapsed_us = std::chrono::duration_cast<std::chrono::microseconds>(now - start_time).count();
    return eventTimeUs(next_event) <= elapsed_us || reset_pending;
  }

  bool handle(UMockdevIoctlClient* client)
  {
    const gulong request = umockdev_ioctl_client_get_request(client);
    UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
    std::lock_guard<std::mutex> lock(mutex);
    if (!plugged)
    {
      // Like the kernel after a disconnect: URBs in flight complete with -ESHUTDOWN, then
      // everything fails with ENODEV.
      if ((request == USBDEVFS_REAPURB || request == USBDEVFS_REAPURBNDELAY) && !dead.empty())
      {
        UMockdevIoctlData* u = dead.front();
        dead.pop_front();
        reinterpret_cast<usbdevfs_urb*>(u->data)->status = -ESHUTDOWN;
        reinterpret_cast<usbdevfs_urb*>(u->data)->actual_length = 0;
        handOver(client, arg, u);
        return true;
      }
      umockdev_ioctl_client_complete(client, -1, ENODEV);
      return true;
    }
    switch (request)
    {
      case USBDEVFS_GET_CAPABILITIES:
      {
        UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, sizeof(guint32), nullptr);
        *reinterpret_cast<guint32*>(d->data) = USBDEVFS_CAP_BULK_CONTINUATION | USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
                                                USBDEVFS_CAP_REAP_AFTER_DISCONNECT | USBDEVFS_CAP_ZERO_PACKET;
        umockdev_ioctl_data_unref(d);
        umockdev_ioctl_client_complete(client, 0, 0);
        return true;
      }
      case USBDEVFS_CLAIMINTERFACE:
      case USBDEVFS_RELEASEINTERFACE:
      case USBDEVFS_CLEAR_HALT:
      case USBDEVFS_RESET:
      case USBDEVFS_RESETEP:
      case USBDEVFS_SETCONFIGURATION:
      case USBDEVFS_SETINTERFACE:
        umockdev_ioctl_client_complete(client, 0, 0);
        return true;
      case USBDEVFS_CONNECTINFO:
      {
        UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_connectinfo), nullptr);
        auto* ci = reinterpret_cast<usbdevfs_connectinfo*>(d->data);
        ci->devnum = 7;
        ci->slow = 0;
        umockdev_ioctl_data_unref(d);
        umockdev_ioctl_client_complete(client, 0, 0);
        return true;
      }
      case USBDEVFS_SUBMITURB:
        return submit(client, arg);
      case USBDEVFS_REAPURB:
      case USBDEVFS_REAPURBNDELAY:
        return reap(client, arg);
      case USBDEVFS_DISCARDURB:
      {
        const gulong addr = reinterpret_cast<gulong>(*reinterpret_cast<void**>(arg->data));
        for (auto it = bulk_in.begin(); it != bulk_in.end(); ++it)
          if ((*it)->client_addr == addr)
          {
            discarded.push_back(*it);
            bulk_in.erase(it);
            umockdev_ioctl_client_complete(client, 0, 0);
            return true;
          }
        umockdev_ioctl_client_complete(client, -1, EINVAL);
        return true;
      }
      default:
        return false;  // let umockdev handle/forward anything else
    }
  }

  bool submit(UMockdevIoctlClient* client, UMockdevIoctlData* arg)
  {
    UMockdevIoctlData* urb_data = umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr);
    auto* urb = reinterpret_cast<usbdevfs_urb*>(urb_data->data);
    UMockdevIoctlData* buf_data =
        umockdev_ioctl_data_resolve(urb_data, G_STRUCT_OFFSET(usbdevfs_urb, buffer), urb->buffer_length, nullptr);
    uint8_t* buf = buf_data->data;
    umockdev_ioctl_data_unref(buf_data);  // still owned by urb_data
    if (urb->type == USBDEVFS_URB_TYPE_CONTROL)
    {
      const uint8_t bm = buf[0], req = buf[1];
      const uint16_t value = static_cast<uint16_t>(buf[2] | (buf[3] << 8));
      const uint16_t index = static_cast<uint16_t>(buf[4] | (buf[5] << 8));
      const uint16_t length = static_cast<uint16_t>(buf[6] | (buf[7] << 8));
      urb->status = 0;
      urb->actual_length = 0;
      if (bm == 0x80 && req == 6 && (value >> 8) == 3)  // GET_DESCRIPTOR(string)
      {
        const uint8_t idx = value & 0xFF;
        std::vector<uint8_t> d;
        if (idx == 0)
          d = {4, 3, 0x09, 0x04};
        else if (idx == 1)
          d = stringDescriptor("iniLabs");
        else if (idx == 2)
          d = stringDescriptor("DVS128");
        else if (idx == 3)
          d = stringDescriptor(serial);
        const size_t n = std::min<size_t>(d.size(), length);
        std::memcpy(buf + 8, d.data(), n);
        urb->actual_length = static_cast<int>(n);
        if (d.empty())
          urb->status = -EPIPE;
      }
      else if (bm == 0x40)  // vendor request to the device
      {
        ControlRecord rec{bm, req, value, index, std::vector<uint8_t>(buf + 8, buf + 8 + length)};
        controls.push_back(rec);
        urb->actual_length = length;
        const auto now = Clock::now();
        if (req == 0xB3 && !streaming)
        {
          streaming = true;
          start_time = now - std::chrono::microseconds(eventTimeUs(next_event));
          last_flush = now;
        }
        else if (req == 0xB4)
          streaming = false;
        else if (req == 0xBB)
        {
          reset_pending = true;
          reset_at_us = streaming ? eventTimeUs(next_event) : 0;
          last_word_dev_us = 0;
        }
      }
      else
        urb->status = -EPIPE;
      ready.push_back(urb_data);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
    if (urb->type == USBDEVFS_URB_TYPE_BULK && urb->endpoint == 0x86)
    {
      bulk_in.push_back(urb_data);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
    umockdev_ioctl_data_unref(urb_data);
    umockdev_ioctl_client_complete(client, -1, EINVAL);
    return true;
  }

  void handOver(UMockdevIoctlClient* client, UMockdevIoctlData* arg, UMockdevIoctlData* urb_data)
  {
    UMockdevIoctlData* ptr = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpointer), nullptr);
    umockdev_ioctl_data_set_ptr(ptr, 0, urb_data);
    umockdev_ioctl_data_unref(ptr);
    umockdev_ioctl_data_unref(urb_data);
    umockdev_ioctl_client_complete(client, 0, 0);
  }

  bool reap(UMockdevIoctlClient* client, UMockdevIoctlData* arg)
  {
    if (!discarded.empty())
    {
      UMockdevIoctlData* u = discarded.front();
      discarded.pop_front();
      reinterpret_cast<usbdevfs_urb*>(u->data)->status = -ENOENT;
      reinterpret_cast<usbdevfs_urb*>(u->data)->actual_length = 0;
      handOver(client, arg, u);
      return true;
    }
    if (!ready.empty())
    {
      UMockdevIoctlData* u = ready.front();
      ready.pop_front();
      handOver(client, arg, u);
      return true;
    }
    const auto now = Clock::now();
    if (!bulk_in.empty() && eventsDue(now))
    {
      UMockdevIoctlData* u = bulk_in.front();
      auto* urb = reinterpret_cast<usbdevfs_urb*>(u->data);
      // Complete when a buffer's worth is due or the flush interval has passed.
      const int64_t elapsed_us = std::chrono::duration_cast<std::chrono::microseconds>(now - start_time).count();
      const uint64_t capacity_events = static_cast<uint64_t>(urb->buffer_length) / 4 / 2;
      const bool full = eventTimeUs(next_event + capacity_events) <= elapsed_us;
      const bool flush = now - last_flush >= std::chrono::microseconds(flush_us);
      if (full || flush || reset_pending)
      {
        // urb->buffer points at the local copy resolved at submission.
        const size_t n = generate(static_cast<uint8_t*>(urb->buffer), static_cast<size_t>(urb->buffer_length), now);
        urb->actual_length = static_cast<int>(n);
        urb->status = 0;
        bulk_in.pop_front();
        last_flush = now;
        ++urbs_completed;
        handOver(client, arg, u);
        if (record)
          completions.push_back(Completion{events_sent, Clock::now()});
        return true;
      }
    }
    umockdev_ioctl_client_complete(client, -1, EAGAIN);
    return true;
  }

  void addDevice()
  {
    std::vector<uint8_t> desc = {
        // device: USB 2.0, class 0, EP0 64, 152a:8400, bcdDevice 0x00<fw>, strings 1 2 3, 1 config
        0x12, 0x01, 0x00, 0x02, 0x00, 0x00, 0x00, 0x40, 0x2a, 0x15, 0x00, 0x84, static_cast<uint8_t>(firmware & 0xFF),
        static_cast<uint8_t>(firmware >> 8), 0x01, 0x02, 0x03, 0x01,
        // configuration 1: total 25 bytes, 1 interface, bus powered 100 mA
        0x09, 0x02, 0x19, 0x00, 0x01, 0x01, 0x00, 0x80, 0x32,
        // interface 0: 1 endpoint, vendor class
        0x09, 0x04, 0x00, 0x00, 0x01, 0xff, 0x00, 0x00, 0x00,
        // endpoint 0x86 bulk IN, 512 bytes
        0x07, 0x05, 0x86, 0x02, 0x00, 0x02, 0x00};
    if (!attached)
    {
      umockdev_testbed_attach_ioctl(testbed, kDevNode, handler, nullptr);
      attached = true;
    }
    const std::string description = std::string("P: ") + (kSysPath + 4) +
                                    "\n"
                                    "N: bus/usb/003/007\n"
                                    "E: SUBSYSTEM=usb\n"
                                    "E: DRIVER=usb\n"
                                    "E: BUSNUM=003\n"
                                    "E: DEVNUM=007\n"
                                    "E: DEVNAME=/dev/bus/usb/003/007\n"
                                    "E: DEVTYPE=usb_device\n"
                                    "E: PRODUCT=152a/8400/" +
                                    std::to_string(firmware) +
                                    "\n"
                                    "A: bConfigurationValue=1\\n\n"
                                    "A: busnum=3\\n\n"
                                    "A: devnum=7\\n\n"
                                    "A: speed=480\\n\n"
                                    "A: idVendor=152a\\n\n"
                                    "A: idProduct=8400\\n\n"
                                    "A: serial=" +
                                    serial + "\\n\n" + "H: descriptors=" + hex(desc) + "\n";
    GError* error = nullptr;
    if (!umockdev_testbed_add_from_string(testbed, description.c_str(), &error))
    {
      std::fprintf(stderr, "umockdev: cannot add the DVS128: %s\n", error ? error->message : "?");
      g_clear_error(&error);
      std::abort();
    }
  }
};

Dvs128Emulator::Dvs128Emulator(const std::string& serial, uint16_t firmware) : impl_(new Impl)
{
  impl_->serial = serial;
  impl_->firmware = firmware;
  impl_->testbed = umockdev_testbed_new();
  impl_->handler = umockdev_ioctl_base_new();
  impl_->signal_id =
      g_signal_connect(impl_->handler, "handle-ioctl", G_CALLBACK(&Impl::onIoctl), impl_.get());
  plug();
}

Dvs128Emulator::~Dvs128Emulator()
{
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->plugged = false;
  }
  umockdev_testbed_detach_ioctl(impl_->testbed, kDevNode, nullptr);
  g_signal_handler_disconnect(impl_->handler, impl_->signal_id);
  for (auto* q : {&impl_->bulk_in, &impl_->ready, &impl_->discarded})
    for (UMockdevIoctlData* d : *q)
      umockdev_ioctl_data_unref(d);
  g_object_unref(impl_->handler);
  g_object_unref(impl_->testbed);
}

void Dvs128Emulator::plug()
{
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->plugged)
      return;
    impl_->plugged = true;
    impl_->streaming = false;
    impl_->reset_pending = false;
  }
  impl_->addDevice();
}

void Dvs128Emulator::unplug()
{
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (!impl_->plugged)
      return;
    impl_->plugged = false;
    impl_->streaming = false;
    for (auto* q : {&impl_->bulk_in, &impl_->ready, &impl_->discarded})
    {
      for (UMockdevIoctlData* d : *q)
        impl_->dead.push_back(d);
      q->clear();
    }
  }
  umockdev_testbed_remove_device(impl_->testbed, kSysPath);
}

bool Dvs128Emulator::plugged() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->plugged;
}

void Dvs128Emulator::setEventRate(double r)
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->rate = r;
}

void Dvs128Emulator::setFlushIntervalUs(int us)
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->flush_us = us;
}

void Dvs128Emulator::setEventLimit(uint64_t n)
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->limit = n;
}

std::vector<ControlRecord> Dvs128Emulator::controls() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->controls;
}

void Dvs128Emulator::clearControls()
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->controls.clear();
}

uint64_t Dvs128Emulator::eventsSent() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->events_sent;
}

uint64_t Dvs128Emulator::urbsCompleted() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->urbs_completed;
}

void Dvs128Emulator::recordCompletions(bool on)
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->record = on;
  if (on)
    impl_->completions.reserve(1 << 20);
}

std::vector<Dvs128Emulator::Completion> Dvs128Emulator::completions() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->completions;
}

bool Dvs128Emulator::streaming() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->streaming;
}

void reexecUnderUmockdev(int argc, char** argv)
{
  const char* preload = std::getenv("LD_PRELOAD");
  if (preload && std::strstr(preload, "umockdev-preload"))
    return;
  std::vector<char*> args;
  static char wrapper[] = "/usr/bin/umockdev-wrapper";
  args.push_back(wrapper);
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0)
    return;
  self[n] = '\0';
  args.push_back(self);
  for (int i = 1; i < argc; ++i)
    args.push_back(argv[i]);
  args.push_back(nullptr);
  ::execv(wrapper, args.data());
  std::perror("exec umockdev-wrapper");
}
}  // namespace dvs_driver_test
