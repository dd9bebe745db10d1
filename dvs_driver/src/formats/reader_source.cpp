#include <dvs_driver/formats/reader_source.h>

namespace dvs_driver
{
FormatReaderSource::FormatReaderSource(const std::string& path)
  : FormatReaderSource(path, [path] { return openEventFileReader(path); })
{
}

FormatReaderSource::FormatReaderSource(const std::string& path, std::function<std::unique_ptr<EventFileReader>()> open)
  : path_(path), open_(std::move(open)), reader_(open_())
{
  info_.name = path;
  info_.width = reader_->width();
  info_.height = reader_->height();
  // No sensor model is named by these formats (the camera name becomes "dvs-file" unless set).
  info_.format = reader_->formatName();
  info_.expected_events = reader_->expectedEvents();
}

size_t FormatReaderSource::read(EventVector& out, size_t max_events)
{
  const size_t before = out.size();
  // A reader may append fewer than asked before its end; keep asking until it has no more.
  while (out.size() - before < max_events && reader_->read(out, max_events - (out.size() - before)))
  {
  }
  return out.size() - before;
}

void FormatReaderSource::rewind() { reader_ = open_(); }

EventChecks FormatReaderSource::checks() const
{
  EventChecks c;
  c.width = info_.width;
  c.height = info_.height;
  c.outside_sensor = reader_->stats().out_of_range;
  return c;
}
}  // namespace dvs_driver
