#pragma once
// Checked bag writing (library dvs_driver_ros): rosbag errors (rosbag::BagException,
// BagIOException: missing folder, full disk, ...) become a BagWriteError naming the bag and the
// reason, never an uncaught exception (rosbag::Bag's destructor retries a failed write and would
// throw from a destructor, i.e. abort; a failed bag is therefore abandoned, never closed again).
//
// The bag is written to `<path>.tmp` and renamed onto `<path>` by close() (a symlink is followed;
// a path that is not a regular file, e.g. a device, gets the finished bag copied into it with
// the checked writer of checked_write.h).
//
// Usage:
//   dvs_driver::CheckedBagWriter bag(path);                    // throws BagWriteError
//   bag.write("/topic", stamp, msg);                            // throws BagWriteError
//   bag.run([&](rosbag::Bag& b) { writeEventsBag(b, ...); });   // any code using the rosbag::Bag
//   bag.close();                                                // throws BagWriteError
// Without close() (an exception on the way), the destructor discards the temporary file.
#include <dvs_driver/checked_write.h>

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>

#include <cerrno>
#include <memory>
#include <string>

namespace dvs_driver
{
class BagWriteError : public WriteError
{
public:
  using WriteError::WriteError;
};

class CheckedBagWriter
{
public:
  explicit CheckedBagWriter(const std::string& path);
  ~CheckedBagWriter();
  CheckedBagWriter(const CheckedBagWriter&) = delete;
  CheckedBagWriter& operator=(const CheckedBagWriter&) = delete;

  template <class Msg>
  void write(const std::string& topic, const ros::Time& time, const Msg& msg)
  {
    run([&](rosbag::Bag& b) { b.write(topic, time, msg); });
  }

  /// Runs f(bag); a rosbag exception becomes BagWriteError (the bag is abandoned); other
  /// exceptions propagate unchanged (the bag stays usable).
  template <class F>
  void run(F&& f)
  {
    if (!bag_)
      throw BagWriteError(path_, "written to after a failure or after close()");
    errno = 0;
    try
    {
      f(*bag_);
    }
    catch (const rosbag::BagException& e)
    {
      fail("writing failed", e.what(), errno);
    }
  }

  /// Finishes the bag (index, header) and moves it to the path; throws BagWriteError.
  void close();
  const std::string& path() const { return path_; }

private:
  [[noreturn]] void fail(const std::string& what, const std::string& rosbag_message, int err);
  void abandon() noexcept;
  std::string path_;
  WriteTarget target_;
  std::string file_;  ///< the file rosbag writes
  std::unique_ptr<rosbag::Bag> bag_;
};
}  // namespace dvs_driver
