#pragma once
// Test support for the suite's rostests (header-only, used by tests only): run a node's
// executable with its output captured, and wait for a message on /rosout. Waits are on
// conditions with a time limit, never fixed sleeps.
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace dvs_driver
{
namespace testing
{
struct ProcessRun
{
  int status = -1;     ///< exit status; -1 when killed by a signal
  std::string output;  ///< stdout and stderr together
};

/// Runs `command` (a shell command line) to completion.
inline ProcessRun runProcess(const std::string& command)
{
  ProcessRun r;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p)
    return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0)
    r.output.append(buf.data(), n);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// Every message on /rosout from construction on (needs a spinner running).
class RosoutLog
{
public:
  explicit RosoutLog(ros::NodeHandle& nh) : sub_(nh.subscribe("/rosout", 1000, &RosoutLog::onLog, this)) {}

  /// Waits until a message containing `text` arrived (true) or `timeout_s` passed (false).
  bool waitFor(const std::string& text, double timeout_s = 20.0)
  {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] {
      for (const auto& s : log_)
        if (s.find(text) != std::string::npos)
          return true;
      return false;
    });
  }

private:
  void onLog(const rosgraph_msgs::Log::ConstPtr& m)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    log_.push_back(m->msg);
    cv_.notify_all();
  }

  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<std::string> log_;
  ros::Subscriber sub_;
};
}  // namespace testing
}  // namespace dvs_driver
