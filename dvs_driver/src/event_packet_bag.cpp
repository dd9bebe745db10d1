// event_camera_msgs/EventPacket bags through rosbag's type-agnostic access; see
// event_packet_bag.h.
#include <dvs_driver/event_packet_bag.h>
#include <dvs_driver/formats/event_packet_decoder.h>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <ros/serialization.h>

#include <sys/stat.h>

#include <algorithm>
#include <cstring>
#include <set>

namespace dvs_driver
{
const char* const kEventPacketDefinition =
    "# A packet of events in an encoded format (ros-event-camera event_camera_msgs)\n"
    "std_msgs/Header header\n"
    "uint32 height\n"
    "uint32 width\n"
    "uint64 seq\n"
    "uint64 time_base\n"
    "string encoding\n"
    "bool is_bigendian\n"
    "uint8[] events\n"
    "\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "uint32 seq\n"
    "time stamp\n"
    "string frame_id\n";

namespace
{
class Parser
{
public:
  Parser(const uint8_t* d, size_t n, std::string& error) : d_(d), n_(n), error_(error) {}
  template <class T>
  bool get(T& v, const char* field)
  {
    if (!need(sizeof(T), field))
      return false;
    std::memcpy(&v, d_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  bool bytes(const uint8_t*& p, size_t& len, const char* field)
  {
    uint32_t n = 0;
    if (!get(n, field) || !need(n, field))
      return false;
    p = d_ + pos_;
    len = n;
    pos_ += n;
    return true;
  }
  bool string(std::string& s, const char* field)
  {
    const uint8_t* p = nullptr;
    size_t len = 0;
    if (!bytes(p, len, field))
      return false;
    s.assign(reinterpret_cast<const char*>(p), len);
    return true;
  }
  size_t left() const { return n_ - pos_; }

private:
  bool need(size_t k, const char* field)
  {
    if (n_ - pos_ >= k)
      return true;
    error_ = std::string("message too short for field '") + field + "' (" + std::to_string(k) + " bytes needed at byte " +
             std::to_string(pos_) + " of " + std::to_string(n_) + ")";
    return false;
  }
  const uint8_t* d_;
  size_t n_, pos_ = 0;
  std::string& error_;
};

template <class T>
void put(std::vector<uint8_t>& b, T v)
{
  const size_t at = b.size();
  b.resize(at + sizeof(T));
  std::memcpy(b.data() + at, &v, sizeof(T));
}

void putBytes(std::vector<uint8_t>& b, const void* p, size_t n)
{
  put(b, uint32_t(n));
  const auto* c = static_cast<const uint8_t*>(p);
  b.insert(b.end(), c, c + n);
}
}  // namespace

bool parseEventPacket(const uint8_t* data, size_t size, EventPacketView& m, std::string& error)
{
  Parser p(data, size, error);
  uint32_t sec = 0, nsec = 0;
  uint8_t big = 0;
  if (!p.get(m.header_seq, "header.seq") || !p.get(sec, "header.stamp") || !p.get(nsec, "header.stamp") ||
      !p.string(m.frame_id, "header.frame_id") || !p.get(m.height, "height") || !p.get(m.width, "width") ||
      !p.get(m.seq, "seq") || !p.get(m.time_base, "time_base") || !p.string(m.encoding, "encoding") ||
      !p.get(big, "is_bigendian") || !p.bytes(m.events, m.events_size, "events"))
    return false;
  m.stamp_ns = int64_t(sec) * 1000000000 + nsec;
  m.is_bigendian = big != 0;
  if (p.left() != 0)
  {
    error = std::to_string(p.left()) + " bytes left over after the events field";
    return false;
  }
  return true;
}

std::vector<uint8_t> serializeEventPacket(const EventPacketView& m)
{
  std::vector<uint8_t> b;
  b.reserve(64 + m.frame_id.size() + m.encoding.size() + m.events_size);
  put(b, m.header_seq);
  put(b, uint32_t(m.stamp_ns / 1000000000));
  put(b, uint32_t(m.stamp_ns % 1000000000));
  putBytes(b, m.frame_id.data(), m.frame_id.size());
  put(b, m.height);
  put(b, m.width);
  put(b, m.seq);
  put(b, m.time_base);
  putBytes(b, m.encoding.data(), m.encoding.size());
  put(b, uint8_t(m.is_bigendian));
  putBytes(b, m.events, m.events_size);
  return b;
}

namespace
{
void openBag(rosbag::Bag& bag, const std::string& path)
{
  try
  {
    bag.open(path, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    throw EventFormatError(path + ": cannot be read as a ROS 1 bag (" + e.what() + ")");
  }
}

std::vector<std::string> packetTopics(rosbag::Bag& bag, std::string* others)
{
  rosbag::View all(bag);
  std::set<std::string> topics, other;
  for (const rosbag::ConnectionInfo* c : all.getConnections())
  {
    if (c->datatype == kEventPacketType)
      topics.insert(c->topic);
    else
      other.insert(c->topic + " (" + c->datatype + ")");
  }
  if (others)
    for (const auto& o : other)
      *others += (others->empty() ? "" : ", ") + o;
  return std::vector<std::string>(topics.begin(), topics.end());
}

class EventPacketBagReader : public EventFileReader
{
public:
  EventPacketBagReader(const std::string& path, const std::string& topic) : path_(path)
  {
    struct stat st
    {
    };
    if (::stat(path.c_str(), &st) == 0)
      file_size_ = uint64_t(st.st_size);
    openBag(bag_, path);
    std::string others;
    const auto topics = packetTopics(bag_, &others);
    if (topic.empty())
    {
      if (topics.empty())
        fail(std::string("no ") + kEventPacketType + " messages (the bag holds " +
             (others.empty() ? std::string("no messages") : others) + ")");
      topic_ = topics.front();
      if (topics.size() > 1)
        warn("several EventPacket topics: reading " + topic_ + ", not the " + std::to_string(topics.size() - 1) +
             " others");
    }
    else
    {
      topic_ = topic;
      if (std::find(topics.begin(), topics.end(), topic) == topics.end())
        fail("topic " + topic + " has no " + kEventPacketType + " messages (the bag holds " +
             (topics.empty() ? std::string("") : "EventPacket topics " + topics.front() + (topics.size() > 1 ? ", ..." : "") +
                                                    "; ") +
             (others.empty() ? std::string("nothing else") : others) + ")");
    }
    view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topic_));
    for (const rosbag::ConnectionInfo* c : view_->getConnections())
      if (c->md5sum != kEventPacketMd5 && c->md5sum != "*")
        fail("topic " + topic_ + " has " + kEventPacketType + " with MD5 " + c->md5sum + ", not " + kEventPacketMd5 +
             " (another definition of the message)");
    total_messages_ = view_->size();
    it_ = view_->begin();
    // The first message fixes encoding and size (and an unsupported encoding fails here).
    while (encoding_.empty() && it_ != view_->end())
      nextMessage();
  }

  bool read(EventVector& out, size_t max_events) override
  {
    size_t appended = 0;
    while (appended < max_events)
    {
      if (pending_pos_ < pending_.size())
      {
        const size_t k = std::min(max_events - appended, pending_.size() - pending_pos_);
        out.insert(out.end(), pending_.begin() + pending_pos_, pending_.begin() + pending_pos_ + k);
        pending_pos_ += k;
        appended += k;
        delivered_ += k;
      }
      else if (!nextMessage())
        break;
    }
    return appended > 0;
  }

  uint32_t width() const override { return width_; }
  uint32_t height() const override { return height_; }
  std::string formatName() const override
  {
    return std::string("ROS 1 bag, ") + kEventPacketType + " (" + (encoding_.empty() ? "no messages" : encoding_) +
           ") on " + topic_;
  }
  ReaderStats stats() const override
  {
    ReaderStats s = decoder_.stats();
    s.events = delivered_;
    s.file_size = file_size_;
    s.bytes_read = total_messages_ ? uint64_t(double(file_size_) * double(messages_read_) / double(total_messages_))
                                   : file_size_;
    if (done_)
      s.bytes_read = file_size_;
    s.damaged_packets += damaged_;
    s.warnings.insert(s.warnings.begin(), warnings_.begin(), warnings_.end());
    return s;
  }
  size_t takeTriggers(std::vector<TriggerEvent>& out) override
  {
    const size_t n = triggers_.size();
    out.insert(out.end(), triggers_.begin(), triggers_.end());
    triggers_.clear();
    return n;
  }

private:
  [[noreturn]] void fail(const std::string& what) const { throw EventFormatError(path_ + ": " + what); }

  void warn(const std::string& text)
  {
    const std::string kind = text.substr(0, text.find(':'));
    for (const auto& w : warnings_)
      if (w.compare(0, kind.size(), kind) == 0)
        return;
    warnings_.push_back(text);
  }

  /// Decode the next message into pending_; false at the end or for a skipped message.
  bool nextMessage()
  {
    pending_.clear();
    pending_pos_ = 0;
    if (it_ == view_->end())
    {
      done_ = true;
      return false;
    }
    const rosbag::MessageInstance& m = *it_;
    buf_.resize(m.size());
    ros::serialization::OStream os(buf_.data(), uint32_t(buf_.size()));
    m.write(os);
    ++it_;
    ++messages_read_;
    EventPacketView msg;
    std::string error;
    if (!parseEventPacket(buf_.data(), buf_.size(), msg, error))
    {
      ++damaged_;
      warn("damaged: message " + std::to_string(messages_read_ - 1) + " on " + topic_ + ": " + error + "; skipped");
      done_ = it_ == view_->end();
      return !done_;
    }
    if (msg.is_bigendian)
      fail("message " + std::to_string(messages_read_ - 1) + " has is_bigendian set: big-endian payloads are not supported");
    if (encoding_.empty())
    {
      if (!formats::EventPacketDecoder::supports(msg.encoding))
        fail("EventPacket encoding '" + msg.encoding + "' is not supported (evt3, mono and libcaer are)");
      encoding_ = msg.encoding;
      width_ = msg.width;
      height_ = msg.height;
    }
    else if (have_seq_ && msg.seq != last_seq_ + 1)
      warn("gap: EventPacket seq jumps from " + std::to_string(last_seq_) + " to " + std::to_string(msg.seq) +
           " (lost messages)");
    have_seq_ = true;
    last_seq_ = msg.seq;
    try
    {
      decoder_.decode(msg.encoding, msg.width, msg.height, msg.time_base, msg.events, msg.events_size, pending_,
                      triggers_.size() < kMaxKept ? &triggers_ : nullptr);
    }
    catch (const EventFormatError& e)
    {
      fail(e.what());
    }
    return true;
  }

  static constexpr size_t kMaxKept = 1 << 20;
  std::string path_, topic_, encoding_;
  uint64_t file_size_ = 0;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  uint64_t total_messages_ = 0, messages_read_ = 0, delivered_ = 0, damaged_ = 0;
  bool done_ = false, have_seq_ = false;
  uint64_t last_seq_ = 0;
  uint32_t width_ = 0, height_ = 0;
  std::vector<uint8_t> buf_;
  formats::EventPacketDecoder decoder_;
  EventVector pending_;
  size_t pending_pos_ = 0;
  std::vector<TriggerEvent> triggers_;
  std::vector<std::string> warnings_;
};
}  // namespace

std::vector<std::string> eventPacketTopics(const std::string& bag_path)
{
  rosbag::Bag bag;
  openBag(bag, bag_path);
  return packetTopics(bag, nullptr);
}

std::unique_ptr<EventFileReader> openEventPacketBag(const std::string& bag_path, const std::string& topic)
{
  return std::make_unique<EventPacketBagReader>(bag_path, topic);
}
}  // namespace dvs_driver
