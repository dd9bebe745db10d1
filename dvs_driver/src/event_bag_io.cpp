#include <dvs_driver/checked_bag.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_file.h>
#include <dvs_driver/event_packet_bag.h>
#include <dvs_driver/formats/reader_source.h>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <map>
#include <sys/stat.h>

namespace dvs_driver
{
namespace
{
constexpr int64_t kNsPerSec = 1000000000LL;
}

ros::Time nsToRosTime(int64_t t_ns)
{
  if (t_ns < 0 || t_ns / kNsPerSec > static_cast<int64_t>(UINT32_MAX))
    throw EventBagError("time " + std::to_string(t_ns) +
                        " ns cannot be stored as a ros::Time (must be in [0, 2^32) s); shift the time stamps first");
  ros::Time t;
  t.sec = static_cast<uint32_t>(t_ns / kNsPerSec);
  t.nsec = static_cast<uint32_t>(t_ns % kNsPerSec);
  return t;
}

void appendToMessage(const Event* begin, const Event* end, dvs_msgs::EventArray& msg)
{
  const size_t old = msg.events.size();
  msg.events.resize(old + static_cast<size_t>(end - begin));
  dvs_msgs::Event* out = msg.events.data() + old;
  for (const Event* e = begin; e != end; ++e, ++out)
  {
    out->x = e->x;
    out->y = e->y;
    out->ts = nsToRosTime(e->t_ns);
    out->polarity = e->polarity;
  }
}

dvs_msgs::EventArrayPtr toMessage(const Event* begin, const Event* end, uint32_t width, uint32_t height,
                                  const std::string& frame_id)
{
  dvs_msgs::EventArrayPtr msg(new dvs_msgs::EventArray);
  msg->width = width;
  msg->height = height;
  msg->header.frame_id = frame_id;
  appendToMessage(begin, end, *msg);
  if (begin != end)
    msg->header.stamp = msg->events.back().ts;
  return msg;
}

dvs_msgs::EventArrayPtr toMessage(const EventStream& stream, const std::string& frame_id)
{
  const Event* b = stream.events.data();
  return toMessage(b, b + stream.events.size(), stream.width, stream.height, frame_id);
}

void appendFromMessage(const dvs_msgs::EventArray& msg, EventVector& out)
{
  const size_t old = out.size();
  out.resize(old + msg.events.size());
  Event* o = out.data() + old;
  for (const dvs_msgs::Event& e : msg.events)
  {
    o->t_ns = rosTimeToNs(e.ts);
    o->x = e.x;
    o->y = e.y;
    o->polarity = e.polarity;
    ++o;
  }
}

std::string checkSerializedEventArray(const uint8_t* data, size_t size)
{
  // Layout: uint32 seq, uint32 sec, uint32 nsec, uint32 len + frame_id, uint32 height,
  // uint32 width, uint32 count, then count x 13 bytes (uint16 x, uint16 y, time ts, uint8 pol).
  auto u32 = [&](size_t at) {
    return static_cast<uint32_t>(data[at]) | static_cast<uint32_t>(data[at + 1]) << 8 |
           static_cast<uint32_t>(data[at + 2]) << 16 | static_cast<uint32_t>(data[at + 3]) << 24;
  };
  if (size < 16)
    return "message of " + std::to_string(size) + " bytes is shorter than an EventArray header";
  const uint64_t frame_len = u32(12);
  const uint64_t count_at = 16 + frame_len + 8;
  if (count_at + 4 > size)
    return "frame_id length " + std::to_string(frame_len) + " runs past the message's " + std::to_string(size) +
           " bytes";
  const uint64_t count = u32(count_at);
  if (count * 13 > size - count_at - 4)
    return "event count " + std::to_string(count) + " needs " + std::to_string(count * 13) + " bytes, the message has " +
           std::to_string(size - count_at - 4);
  return "";
}

EventStream fromMessage(const dvs_msgs::EventArray& msg)
{
  EventStream s;
  s.width = msg.width;
  s.height = msg.height;
  appendFromMessage(msg, s.events);
  return s;
}

struct BagEventSource::Reader
{
  rosbag::Bag bag;
  std::unique_ptr<rosbag::View> view;
  rosbag::View::iterator it;
  dvs_msgs::EventArrayConstPtr pending;
  size_t pending_next = 0;
  std::vector<uint8_t> raw;  ///< the serialized message, checked before deserializing
};

namespace
{
/// The message, deserialized once its event count is known to fit its bytes (else EventBagError
/// naming the file and the message time).
dvs_msgs::EventArrayConstPtr instantiateChecked(const rosbag::MessageInstance& m, std::vector<uint8_t>& raw,
                                                const std::string& name)
{
  raw.resize(m.size());
  ros::serialization::OStream out(raw.data(), static_cast<uint32_t>(raw.size()));
  m.write(out);
  const std::string why = checkSerializedEventArray(raw.data(), raw.size());
  if (!why.empty())
    throw EventBagError(name + ": corrupt EventArray message at bag time " + std::to_string(m.getTime().toSec()) +
                        " s: " + why);
  return m.instantiate<dvs_msgs::EventArray>();
}
}  // namespace

BagEventSource::BagEventSource(const std::string& path, const std::string& topic) : reader_(new Reader)
{
  info_.name = path;
  info_.format = "ROS bag, dvs_msgs/EventArray on " + topic;
  struct stat st;
  if (::stat(path.c_str(), &st) != 0)
    throw EventBagError(path + ": bag file does not exist");
  try
  {
    reader_->bag.open(path, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    throw EventBagError(path + ": cannot open bag: " + e.what());
  }
  try
  {
    rosbag::View all(reader_->bag);
    std::map<std::string, std::string> topics;
    const std::string want_type = ros::message_traits::DataType<dvs_msgs::EventArray>::value();
    bool found = false;
    for (const rosbag::ConnectionInfo* c : all.getConnections())
    {
      topics[c->topic] = c->datatype;
      if (c->topic == topic)
      {
        found = true;
        if (c->datatype != want_type)
          throw EventBagError(path + ": topic " + topic + " has type " + c->datatype + ", expected " + want_type);
        if (c->md5sum != ros::message_traits::MD5Sum<dvs_msgs::EventArray>::value())
          throw EventBagError(path + ": topic " + topic + " has MD5 sum " + c->md5sum +
                              ", not that of dvs_msgs/EventArray (" +
                              ros::message_traits::MD5Sum<dvs_msgs::EventArray>::value() + ")");
      }
    }
    if (!found)
    {
      std::string list;
      for (const auto& kv : topics)
        list += (list.empty() ? "" : ", ") + kv.first + " [" + kv.second + "]";
      throw EventBagError(path + ": no topic " + topic + " in the bag; topics present: " +
                          (list.empty() ? std::string("(none)") : list));
    }
    reader_->view.reset(new rosbag::View(reader_->bag, rosbag::TopicQuery(topic)));
    // The sensor size: that of the first message that states one (usually the first).
    for (const rosbag::MessageInstance& m : *reader_->view)
    {
      dvs_msgs::EventArrayConstPtr msg = instantiateChecked(m, reader_->raw, path);
      if (msg && (msg->width != 0 || msg->height != 0))
      {
        info_.width = msg->width;
        info_.height = msg->height;
        break;
      }
    }
  }
  catch (const rosbag::BagException& e)
  {
    throw EventBagError(path + ": error reading bag: " + e.what());
  }
  rewind();
}

BagEventSource::~BagEventSource() = default;

void BagEventSource::rewind()
{
  reader_->it = reader_->view->begin();
  reader_->pending.reset();
  reader_->pending_next = 0;
}

size_t BagEventSource::read(EventVector& out, size_t max_events)
{
  Reader& r = *reader_;
  size_t n = 0;
  try
  {
    while (n < max_events)
    {
      if (!r.pending)
      {
        if (r.it == r.view->end())
          break;
        r.pending = instantiateChecked(*r.it, r.raw, info_.name);
        ++r.it;
        r.pending_next = 0;
        if (!r.pending)
          continue;
      }
      const size_t take = std::min(max_events - n, r.pending->events.size() - r.pending_next);
      const size_t old = out.size();
      out.resize(old + take);
      for (size_t k = 0; k < take; ++k)
      {
        const dvs_msgs::Event& e = r.pending->events[r.pending_next + k];
        out[old + k] = Event{rosTimeToNs(e.ts), e.x, e.y, static_cast<bool>(e.polarity)};
      }
      n += take;
      r.pending_next += take;
      if (r.pending_next == r.pending->events.size())
        r.pending.reset();
    }
  }
  catch (const rosbag::BagException& e)
  {
    throw EventBagError(info_.name + ": error reading bag: " + e.what());
  }
  return n;
}

EventStream readEventsBag(const std::string& path, const std::string& topic)
{
  BagEventSource source(path, topic);
  EventStream stream;
  stream.width = source.info().width;
  stream.height = source.info().height;
  while (source.read(stream.events, 1 << 20) > 0)
  {
  }
  return stream;
}

namespace
{
/// A bag is read as event_camera_msgs/EventPacket messages when `topic` carries them, or when it
/// is the default topic, the bag has no such topic and holds EventPacket topics (then the first;
/// openEventPacketBag warns about others). Returns false (a dvs_msgs bag: BagEventSource, whose
/// errors list the topics) otherwise, and for files that are not bags.
bool isEventPacketBag(const std::string& path, const std::string& topic, std::string& packet_topic)
{
  std::vector<std::string> packet_topics;
  try
  {
    packet_topics = eventPacketTopics(path);
  }
  catch (const std::exception&)
  {
    return false;  // BagEventSource names the problem
  }
  if (std::find(packet_topics.begin(), packet_topics.end(), topic) != packet_topics.end())
  {
    packet_topic = topic;
    return true;
  }
  if (packet_topics.empty() || topic != kDefaultEventTopic)
    return false;
  try
  {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(topic));
    if (!view.getConnections().empty())
      return false;  // the default topic exists (of whatever type): BagEventSource
  }
  catch (const rosbag::BagException&)
  {
    return false;  // BagEventSource names the problem
  }
  packet_topic = "";
  return true;
}

std::unique_ptr<EventSource> openBagSource(const std::string& path, const std::string& topic)
{
  std::string packet_topic;
  if (isEventPacketBag(path, topic, packet_topic))
    return std::unique_ptr<EventSource>(
        new FormatReaderSource(path, [path, packet_topic] { return openEventPacketBag(path, packet_topic); }));
  return std::unique_ptr<EventSource>(new BagEventSource(path, topic));
}
}  // namespace

std::unique_ptr<EventFileReader> openEventPacketBagFor(const std::string& path, const std::string& topic)
{
  std::string packet_topic;
  if (isEventPacketBag(path, topic, packet_topic))
    return openEventPacketBag(path, packet_topic);
  return nullptr;
}

std::unique_ptr<EventSource> openEventSource(const std::string& path, const std::string& topic)
{
  if (eventFileFormat(path) == EventFileFormat::Bag)
    return openBagSource(path, topic);
  // The formats told apart by their first bytes (Prophesee RAW, AEDAT 3.1/4.0, HDF5); AEDAT 2.0
  // and events.txt as before.
  switch (detectEventFormat(path))
  {
    case EventFormat::PropheseeRaw:
    case EventFormat::Aedat3:
    case EventFormat::Aedat4:
    case EventFormat::Hdf5:
      return std::unique_ptr<EventSource>(new FormatReaderSource(path));
    case EventFormat::RosBag1:
      return openBagSource(path, topic);
    default:
      return openEventFileSource(path);
  }
}

size_t writeEventsBag(rosbag::Bag& bag, const std::string& topic, const EventVector& events, uint32_t width,
                      uint32_t height, int64_t packet_period_ns, const std::string& frame_id,
                      const WriteProgress& progress)
{
  if (packet_period_ns <= 0)
    throw EventBagError("packet period must be > 0 ns, got " + std::to_string(packet_period_ns));
  size_t written = 0;
  size_t i = 0;
  dvs_msgs::EventArray msg;
  msg.width = width;
  msg.height = height;
  msg.header.frame_id = frame_id;
  while (i < events.size())
  {
    if (events[i].t_ns < 0)
      nsToRosTime(events[i].t_ns);  // throws with a clear message
    const int64_t period = events[i].t_ns / packet_period_ns;
    size_t j = i + 1;
    while (j < events.size() && events[j].t_ns / packet_period_ns == period)
    {
      if (events[j].t_ns < events[j - 1].t_ns)
        throw EventBagError("event " + std::to_string(j) + " goes back in time (" + std::to_string(events[j].t_ns) +
                            " ns after " + std::to_string(events[j - 1].t_ns) + " ns)");
      ++j;
    }
    if (j < events.size() && events[j].t_ns < events[j - 1].t_ns)
      throw EventBagError("event " + std::to_string(j) + " goes back in time (" + std::to_string(events[j].t_ns) +
                          " ns after " + std::to_string(events[j - 1].t_ns) + " ns)");
    msg.events.clear();
    appendToMessage(events.data() + i, events.data() + j, msg);
    msg.header.stamp = msg.events.back().ts;
    ++msg.header.seq;
    bag.write(topic, msg.header.stamp, msg);
    ++written;
    if (progress && (i >> 16) != (j >> 16))
      progress(j);
    i = j;
  }
  if (progress)
    progress(events.size());
  return written;
}

size_t writeEventsBag(CheckedBagWriter& bag, const std::string& topic, const EventVector& events, uint32_t width,
                      uint32_t height, int64_t packet_period_ns, const std::string& frame_id,
                      const WriteProgress& progress)
{
  size_t n = 0;
  bag.run([&](rosbag::Bag& b) {
    n = writeEventsBag(b, topic, events, width, height, packet_period_ns, frame_id, progress);
  });
  return n;
}

size_t writeEventsBag(const std::string& path, const std::string& topic, const EventStream& stream,
                      int64_t packet_period_ns, const std::string& frame_id, const WriteProgress& progress)
{
  CheckedBagWriter bag(path);  // throws BagWriteError naming the bag and the reason
  const size_t n =
      writeEventsBag(bag, topic, stream.events, stream.width, stream.height, packet_period_ns, frame_id, progress);
  bag.close();
  return n;
}
}  // namespace dvs_driver
