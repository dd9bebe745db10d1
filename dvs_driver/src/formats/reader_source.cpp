#include <dvs_driver/formats/reader_source.h>

namespace dvs_driver
{
FormatReaderSource::FormatReaderSource(const std::string& path) : path_(path), reader_(openEventFileReader(path))
{
  info_.name = path;
  info_.width = reader_->width();
  info_.height = reader_->height();
  info_.sensor_name = reader_->formatName();
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

void FormatReaderSource::rewind() { reader_ = openEventFileReader(path_); }

EventChecks FormatReaderSource::checks() const
{
  EventChecks c;
  c.width = info_.width;
  c.height = info_.height;
  c.outside_sensor = reader_->stats().out_of_range;
  return c;
}
}  // namespace dvs_driver
