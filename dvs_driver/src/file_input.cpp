#include <dvs_driver/file_input.h>

#include <chrono>
#include <stdexcept>

namespace dvs_driver
{
FileInput::FileInput(EventStream stream, const std::string& name, const FileInputOptions& options)
  : stream_(std::move(stream)), name_(name), options_(options)
{
  if (options_.speed < 0)
    throw std::invalid_argument("replay speed must be >= 0 (0 = as fast as possible), got " +
                                std::to_string(options_.speed));
  if (options_.chunk_period_ns <= 0 || options_.chunk_max_events == 0)
    throw std::invalid_argument("replay chunks must be > 0");
}

FileInput::~FileInput()
{
  stop();
}

void FileInput::start(EventInputListener& listener)
{
  stopping_ = false;
  thread_ = std::thread(&FileInput::run, this, std::ref(listener));
}

void FileInput::stop()
{
  stopping_ = true;
  if (thread_.joinable())
    thread_.join();
}

void FileInput::run(EventInputListener& listener)
{
  using Clock = std::chrono::steady_clock;
  const EventVector& ev = stream_.events;
  if (ev.empty())
  {
    listener.onEndOfInput();
    return;
  }
  const int64_t span = ev.back().t_ns - ev.front().t_ns;
  int64_t loop_offset = 0;
  EventVector shifted;
  shifted.reserve(options_.chunk_max_events);
  const Clock::time_point wall0 = Clock::now();
  const int64_t t0 = ev.front().t_ns;
  do
  {
    size_t i = 0;
    while (i < ev.size() && !stopping_)
    {
      size_t j = i + 1;
      while (j < ev.size() && j - i < options_.chunk_max_events && ev[j].t_ns - ev[i].t_ns < options_.chunk_period_ns)
        ++j;
      if (options_.speed > 0)
      {
        const double due_s = static_cast<double>(ev[j - 1].t_ns + loop_offset - t0) * 1e-9 / options_.speed;
        const Clock::time_point due = wall0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(due_s));
        // Sleep in short steps so stop() stays responsive.
        while (!stopping_ && Clock::now() < due)
          std::this_thread::sleep_for(std::min<Clock::duration>(due - Clock::now(), std::chrono::milliseconds(20)));
      }
      if (stopping_)
        break;
      if (loop_offset == 0)
        listener.onEvents(ev.data() + i, ev.data() + j);
      else
      {
        shifted.assign(ev.begin() + static_cast<long>(i), ev.begin() + static_cast<long>(j));
        for (Event& e : shifted)
          e.t_ns += loop_offset;
        listener.onEvents(shifted.data(), shifted.data() + shifted.size());
      }
      delivered_ += j - i;
      i = j;
    }
    loop_offset += span + 1000000;  // 1 ms gap between loops
  } while (options_.loop && !stopping_);
  if (!stopping_)
    listener.onEndOfInput();
}
}  // namespace dvs_driver
