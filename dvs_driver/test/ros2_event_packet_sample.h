#pragma once
// Test helper: the EventPacket messages of the ROS 2 bag sample
// (../shared/data/formats/eventpacket_evt3_1280x720_ros2bag.db3), read with sqlite3 and a small
// CDR parser (layout in that directory's README). Test code only (gtests and the rostests' bag
// writer, write_event_packet_bag); errors throw std::runtime_error naming the file.
#include <sqlite3.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace ros2_sample
{
struct Packet
{
  int32_t stamp_sec = 0;
  uint32_t stamp_nsec = 0;
  uint32_t height = 0, width = 0;
  uint64_t seq = 0, time_base = 0;
  std::string frame_id, encoding;
  std::vector<uint8_t> events;
};

/// ROS 2 CDR (little endian) of event_camera_msgs/msg/EventPacket; alignment relative to byte 4.
class Cdr
{
public:
  Cdr(const uint8_t* d, size_t n) : d_(d), n_(n)
  {
    if (n < 4 || d[1] != 1)
      throw std::runtime_error("not a little-endian CDR blob");
  }
  template <class T>
  T get()
  {
    pos_ = (pos_ + sizeof(T) - 1) / sizeof(T) * sizeof(T);
    need(sizeof(T));
    T v;
    std::memcpy(&v, d_ + 4 + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string string()
  {
    const uint32_t len = get<uint32_t>();
    need(len);
    std::string s(reinterpret_cast<const char*>(d_ + 4 + pos_), len ? len - 1 : 0);
    pos_ += len;
    return s;
  }
  std::vector<uint8_t> bytes()
  {
    const uint32_t len = get<uint32_t>();
    need(len);
    std::vector<uint8_t> v(d_ + 4 + pos_, d_ + 4 + pos_ + len);
    pos_ += len;
    return v;
  }

private:
  void need(size_t k) const
  {
    if (4 + pos_ + k > n_)
      throw std::runtime_error("CDR blob too short");
  }
  const uint8_t* d_;
  size_t n_, pos_ = 0;
};

inline std::vector<Packet> readBagPackets(const std::string& path)
{
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
  {
    sqlite3_close(db);
    throw std::runtime_error(path + ": cannot open as sqlite3");
  }
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db, "SELECT data FROM messages ORDER BY timestamp, id", -1, &st, nullptr) != SQLITE_OK)
  {
    sqlite3_close(db);
    throw std::runtime_error(path + ": no ROS 2 bag messages table");
  }
  std::vector<Packet> out;
  while (st && sqlite3_step(st) == SQLITE_ROW)
  {
    Cdr c(static_cast<const uint8_t*>(sqlite3_column_blob(st, 0)), size_t(sqlite3_column_bytes(st, 0)));
    Packet p;
    p.stamp_sec = c.get<int32_t>();
    p.stamp_nsec = c.get<uint32_t>();
    p.frame_id = c.string();
    p.height = c.get<uint32_t>();
    p.width = c.get<uint32_t>();
    p.seq = c.get<uint64_t>();
    p.time_base = c.get<uint64_t>();
    p.encoding = c.string();
    c.get<uint8_t>();  // is_bigendian
    p.events = c.bytes();
    out.push_back(std::move(p));
  }
  sqlite3_finalize(st);
  sqlite3_close(db);
  return out;
}

}  // namespace ros2_sample
