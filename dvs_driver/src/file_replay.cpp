#include <dvs_driver/file_replay.h>

#include <chrono>
#include <stdexcept>

namespace dvs_driver
{
FileReplay::FileReplay(std::unique_ptr<EventSource> source, const FileReplayOptions& options)
  : source_(std::move(source)), options_(options)
{
  if (!source_)
    throw std::invalid_argument("replay: no event source");
  if (options_.speed < 0)
    throw std::invalid_argument("replay speed must be >= 0 (0 = as fast as possible), got " +
                                std::to_string(options_.speed));
  if (options_.chunk_period_ns <= 0 || options_.chunk_max_events == 0)
    throw std::invalid_argument("replay chunks must be > 0");
  if (options_.read_block == 0 || options_.queue_events == 0)
    throw std::invalid_argument("replay read block and queue bound must be > 0");
}

FileReplay::~FileReplay()
{
  stop();
}

void FileReplay::start(EventInputListener& listener)
{
  stopping_ = false;
  // The replay's wall clock starts now (when the driver stamps the first event with file_time
  // replay), not when the first block has been read: reading it delays the first chunks, as a
  // late camera would, instead of shifting every chunk after its events' time.
  started_clock_ = false;
  wall0_ = std::chrono::steady_clock::now();
  if (options_.sensor_width > 0 && options_.sensor_height > 0)
    validator_.setSensor(options_.sensor_width, options_.sensor_height);
  else
    validator_.setSensor(source_->info().width, source_->info().height);
  reader_ = std::thread(&FileReplay::readLoop, this);
  player_ = std::thread(&FileReplay::playLoop, this, std::ref(listener));
}

void FileReplay::stop()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (reader_.joinable())
    reader_.join();
  if (player_.joinable())
    player_.join();
}

bool FileReplay::push(Block block)
{
  std::unique_lock<std::mutex> lock(mutex_);
  // Wait for room; a block alone may exceed the bound only when the queue is empty.
  changed_.wait(lock, [&] {
    return stopping_ || queue_.empty() || queued_events_ + block.events.size() <= options_.queue_events;
  });
  if (stopping_)
    return false;
  queued_events_ += block.events.size();
  if (queued_events_ > max_queued_)
    max_queued_ = queued_events_;
  queue_.push_back(std::move(block));
  lock.unlock();
  changed_.notify_all();
  return true;
}

bool FileReplay::pop(Block& block)
{
  std::unique_lock<std::mutex> lock(mutex_);
  if (block.events.capacity() > 0)
  {
    block.events.clear();
    pool_.push_back(std::move(block.events));
    block.events = EventVector();
  }
  changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
  if (stopping_)
    return false;
  block = std::move(queue_.front());
  queue_.pop_front();
  queued_events_ -= block.events.size();
  lock.unlock();
  changed_.notify_all();
  return true;
}

void FileReplay::readLoop()
{
  int64_t loop_offset = 0;
  bool pass_has_events = false;
  int64_t pass_first = 0, pass_last = 0;
  try
  {
    source_->rewind();
    while (!stopping_)
    {
      Block block;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!pool_.empty())
        {
          block.events = std::move(pool_.back());
          pool_.pop_back();
        }
      }
      if (block.events.capacity() < options_.read_block)
        block.events.reserve(options_.read_block);
      std::string error;
      try
      {
        source_->read(block.events, options_.read_block);
      }
      catch (const std::exception& e)
      {
        error = e.what();  // the events read before the fault still go out, then the error
      }
      if (block.events.empty() && error.empty())
      {
        if (options_.loop && pass_has_events)
        {
          loop_offset += pass_last - pass_first + 1000000;  // 1 ms gap between loops
          pass_has_events = false;
          earlier_passes_.merge(source_->checks());  // the source counts per pass
          source_->rewind();
          continue;
        }
        block.end = true;
        block.checks = currentChecks();
        push(std::move(block));
        return;
      }
      if (!pass_has_events && !block.events.empty())
      {
        pass_has_events = true;
        pass_first = block.events.front().t_ns;
      }
      if (!block.events.empty())
        pass_last = block.events.back().t_ns;
      if (loop_offset != 0)
        for (Event& e : block.events)
          e.t_ns += loop_offset;
      validator_.dropOutside(block.events);  // counted; backwards and duplicates counted, kept
      block.checks = currentChecks();
      if (!error.empty())
      {
        block.error = error;
        push(std::move(block));
        return;
      }
      if (!push(std::move(block)))
        return;
    }
  }
  catch (const std::exception& e)
  {
    Block block;
    block.error = e.what();
    block.checks = currentChecks();
    push(std::move(block));
  }
}

EventChecks FileReplay::currentChecks() const
{
  EventChecks c = validator_.checks();
  c.merge(earlier_passes_);
  c.merge(source_->checks());
  return c;
}

EventChecks FileReplay::checks() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return played_checks_;
}

void FileReplay::reportChecks(EventInputListener& listener, const EventChecks& c, bool last)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    played_checks_ = c;
  }
  const bool grew = c.outside_sensor != reported_.outside_sensor || c.backwards != reported_.backwards ||
                    c.clamped != reported_.clamped || c.duplicates != reported_.duplicates;
  if (c.clean() || !grew)
    return;
  const auto now = std::chrono::steady_clock::now();
  const bool first = reported_.clean();
  if (!first && !last && now - last_report_ < std::chrono::seconds(5))
    return;
  reported_ = c;
  last_report_ = now;
  listener.onWarning(source_->info().name + ": " + c.summary() + (last ? " (in all)" : " (so far)"));
}

void FileReplay::deliver(EventInputListener& listener, EventVector& chunk)
{
  using Clock = std::chrono::steady_clock;
  if (!started_clock_)
  {
    started_clock_ = true;
    t0_ = chunk.front().t_ns;
  }
  if (options_.speed > 0)
  {
    const double due_s = static_cast<double>(chunk.back().t_ns - t0_) * 1e-9 / options_.speed;
    const Clock::time_point due = wall0_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(due_s));
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_until(lock, due, [&] { return stopping_.load(); });
  }
  if (stopping_)
    return;
  listener.onEvents(chunk.data(), chunk.data() + chunk.size());
  delivered_ += chunk.size();
  chunk.clear();
}

void FileReplay::playLoop(EventInputListener& listener)
{
  EventVector chunk;
  chunk.reserve(options_.chunk_max_events);
  Block block;
  while (!stopping_ && pop(block))
  {
    for (const Event& e : block.events)
    {
      if (!chunk.empty() &&
          (chunk.size() >= options_.chunk_max_events || e.t_ns - chunk.front().t_ns >= options_.chunk_period_ns))
      {
        deliver(listener, chunk);
        if (stopping_)
          return;
      }
      chunk.push_back(e);
    }
    const bool last = block.end || !block.error.empty();
    if (last && !chunk.empty())
      deliver(listener, chunk);
    if (stopping_)
      return;
    reportChecks(listener, block.checks, last);
    if (last)
    {
      if (block.error.empty())
        listener.onEndOfInput();
      else
        listener.onInputError(block.error);
      return;
    }
  }
}
}  // namespace dvs_driver
