// The event file readers behind openEventFileReader (Prophesee RAW EVT 2.0/3.0, AEDAT 4.0 with
// its flatbuffers and LZ4/zstd packets, AEDAT 3.1): the first byte chooses a header to steer the
// input into one of them, the rest is the file. Invariants: events inside the size the reader
// states, a bounded amount of output. HDF5 input is skipped: libhdf5 itself is not ours to fuzz.
#include <dvs_driver/formats/event_format.h>

#include "temp_file.h"

#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  if (size < 1)
    return 0;
  static const char* kHeaders[] = {"% evt 3.0\n% format EVT3;height=720;width=1280\n% end\n",
                                   "% evt 2.0\n% geometry 640x480\n% end\n", "#!AER-DAT4.0\r\n",
                                   "#!AER-DAT3.1\r\n#Source 1: DVS128\r\n#!END-HEADER\r\n", ""};
  const std::string header = kHeaders[data[0] % 5];
  std::string file = header + std::string(reinterpret_cast<const char*>(data + 1), size - 1);
  if (file.compare(0, 4, "\x89HDF") == 0)
    return 0;
  const std::string path = fuzz::writeTemp(reinterpret_cast<const uint8_t*>(file.data()), file.size(), ".evt");
  try
  {
    auto reader = dvs_driver::openEventFileReader(path);
    dvs_driver::EventVector events;
    size_t total = 0;
    while (reader->read(events, 4096))
    {
      for (const auto& e : events)
        if ((reader->width() != 0 && e.x >= reader->width()) || (reader->height() != 0 && e.y >= reader->height()))
          std::abort();  // a reader must not deliver events outside the size it states
      total += events.size();
      events.clear();
      if (total > 50000000)
        std::abort();  // far more events than bytes could encode: a loop that does not advance
    }
  }
  catch (const std::exception&)
  {
  }
  return 0;
}
