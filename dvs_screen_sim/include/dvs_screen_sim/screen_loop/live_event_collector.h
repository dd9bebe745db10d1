#pragma once
// The event source of the screen in the loop with a live DVS: packets arrive on another thread
// (a ROS callback) with their host arrival time; the collector learns the DVS's clock from them
// (DvsClockOffset) and keeps the events the procedure asks for. ROS-free, thread-safe.
#include <dvs_screen_sim/screen_loop/screen_loop_procedure.h>

#include <mutex>

namespace dvs_screen_sim
{
namespace screen_loop
{
class LiveEventCollector : public LoopEventSource
{
public:
  /// A packet of events (in time order) that arrived at host time `arrival_host_ns`.
  void addPacket(const dvs_driver::Event* begin, const dvs_driver::Event* end, int64_t arrival_host_ns);

  int64_t dvsTimeNs(int64_t host_ns) const override;
  bool clockValid() const override;
  /// Keeps every event arriving from now on (`from_dvs_ns` is not used: a late packet still
  /// belongs to the window; play() drops what is stamped before its start).
  void keepFrom(int64_t from_dvs_ns) override;
  void drain() override {}
  dvs_driver::EventVector takeKept() override;

  size_t packets() const;

private:
  mutable std::mutex mutex_;
  DvsClockOffset clock_;
  bool keeping_ = false;
  dvs_driver::EventVector kept_;
};
}  // namespace screen_loop
}  // namespace dvs_screen_sim
