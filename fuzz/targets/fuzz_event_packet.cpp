// event_camera_msgs/EventPacket payloads (evt3, mono, libcaer): the first byte chooses the
// encoding and where the payload is cut into two messages (decoder state carried across).
#include <dvs_driver/formats/event_packet_decoder.h>

#include <cstdlib>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  if (size < 2)
    return 0;
  static const char* kEncodings[] = {"evt3", "mono", "libcaer"};
  const std::string encoding = kEncodings[data[0] % 3];
  const size_t cut = 1 + (data[1] * (size - 1)) / 256;
  dvs_driver::formats::EventPacketDecoder decoder;
  dvs_driver::EventVector events;
  std::vector<dvs_driver::TriggerEvent> triggers;
  try
  {
    decoder.decode(encoding, 1280, 720, 0, data + 2, cut > 2 ? cut - 2 : 0, events, &triggers);
    decoder.decode(encoding, 1280, 720, 0, data + std::max<size_t>(cut, 2), size - std::max<size_t>(cut, 2), events,
                   &triggers);
    for (const auto& e : events)
      if (e.x >= 1280 || e.y >= 720)
        std::abort();
  }
  catch (const std::exception&)
  {
  }
  return 0;
}
