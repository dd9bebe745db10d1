#include <dvs_driver/driver_params.h>
#include <dvs_driver/dvs128_biases.h>

namespace dvs_driver
{
size_t DriverParams::publisherQueueSize() const
{
  if (queue_size >= 0)
    return static_cast<size_t>(queue_size);
  return (!file.empty() && !replay_loop) ? 0 : 1000;
}

ParamTable driverParamTable(DriverParams& p)
{
  ParamTable t("dvs_driver");
  t.add("serial_number", p.serial_number, {},
        "camera to open; empty = first found (re-opened by its serial after an unplug)");
  t.add("file", p.file, {},
        "replay this recording instead of a camera: any format of *Event file formats* (detected from its bytes; "
        "bags: topic `/dvs/events`, else the first EventPacket topic); streamed, never read whole");
  t.add("replay_speed", p.replay_speed, "x real time", 0, 1e308, "replay speed; 0 = as fast as possible");
  t.add("replay_loop", p.replay_loop, "start the recording again at its end (times keep increasing)");
  t.add("wait_for_subscriber", p.wait_for_subscriber, "start a replay only when `dvs/events` has a subscriber");
  t.add("file_time", p.file_time, {"replay", "original"},
        "`replay`: the first event is stamped with the time the replay starts; `original`: the file's times "
        "(must be >= 0)");
  t.add("bias_preset", p.bias_preset, {"fast", "standard", "slow"},
        "bias preset (`config/biases/*.yaml`); a parameter `~<bias name>` overrides one bias");
  t.add("packet_period", p.packet_period, "s", 1e-5, 1.0,
        "publish a packet once its events span this long (or it waited this long); dynamic_reconfigure. "
        "Deprecated alias: `packet_period_ms` (ms)");
  t.add("max_events", p.max_events, "events", 1, 10000000,
        "publish a packet once it holds this many events; dynamic_reconfigure");
  t.add("master", p.master, "timestamp master (publishes resets) or slave (follows `dvs/reset_timestamps`)");
  t.add("reset_timestamps_delay", p.reset_timestamps_delay, "s", -1, 1e308,
        "master: reset the timestamps again this long after start (slaves started late); -1 = never");
  t.add("frame_id", p.frame_id, {}, "frame of the packets and camera info (not empty)");
  t.add("camera_name", p.camera_name, {},
        "camera_info_manager name; empty = `DVS128-<serial>` (or `<sensor>-file` for recordings)");
  t.add("camera_info_url", p.camera_info_url, {},
        "camera_info_manager URL; empty = `~/.ros/camera_info/<camera name>.yaml`");
  t.add("camera_info_rate", p.camera_info_rate, "Hz", 0, 1e308,
        "camera_info publishing rate (only while subscribed); 0 = never");
  t.add("reconnect_interval", p.reconnect_interval, "s", 0, 1e308,
        "between re-open attempts of a missing/unplugged camera")
      .min_exclusive = true;
  t.add("transfers", p.transfers, "", 1, 64, "bulk transfers in flight");
  t.add("transfer_size", p.transfer_size, "bytes", 512, 262144, "per bulk transfer, a multiple of 512");
  t.add("queue_size", p.queue_size, "packets", -1, 100000000,
        "per-subscriber publisher queue (see *Slow subscribers*): -1 = automatic (unlimited for a recording "
        "played once, 1000 otherwise), 0 = unlimited");
  t.add("replay_queue_events", p.replay_queue_events, "events", 1024, 100000000,
        "recordings: at most this many events read ahead of the replay (16 bytes each)");
  t.addRule([&p] {
    return p.transfer_size % 512 == 0 ? std::string()
                                      : "transfer_size must be a multiple of 512 bytes (got " +
                                            std::to_string(p.transfer_size) + ")";
  });
  t.addRule([&p] { return p.frame_id.empty() ? std::string("frame_id must not be empty") : std::string(); });
  return t;
}

std::vector<std::string> driverAlsoKnownParams()
{
  std::vector<std::string> names(kDvs128BiasNames.begin(), kDvs128BiasNames.end());
  names.push_back(kDeprecatedPacketPeriodMs);
  return names;
}
}  // namespace dvs_driver
