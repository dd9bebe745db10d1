#pragma once
// Checked file writing (ROS-free): every failure (missing folder, permission, full disk, a
// failed flush or close) throws WriteError naming the file and the OS reason; nothing is reported
// as written unless it was.
//
// A regular file (or a new one) is written to `<path>.tmp` beside it and renamed onto `<path>` at
// commit(), so a failed write never leaves a half-written file under the real name (and never
// destroys the old one). A symlink is followed (the temporary file goes beside its target). A
// path that is not a regular file (a device such as /dev/stdout or /dev/null, a FIFO) is written
// directly, and so is a writable file in a folder where no temporary file can be made.
//
// Usage:
//   dvs_driver::writeFileChecked(path, text);                       // a whole string at once
//   dvs_driver::writeFileChecked(path, [&](std::ostream& out) { out << ...; });
//   dvs_driver::CheckedFileWriter w(path); w.stream() << ...; w.commit();   // streaming
// For cv::imwrite and the like: encode to memory (cv::imencode) and writeFileChecked the bytes.
// Bags: checked_bag.h (library dvs_driver_ros).
#include <functional>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>

namespace dvs_driver
{
/// A file could not be written. what() = "<path>: <what failed>: <OS reason>".
class WriteError : public std::runtime_error
{
public:
  WriteError(const std::string& path, const std::string& message)
    : std::runtime_error(path + ": " + message), path_(path)
  {
  }
  const std::string& path() const { return path_; }

private:
  std::string path_;
};

/// Where a checked write goes: `target` (the path, symlinks resolved) and, when `target` is a
/// regular file or does not exist yet, the temporary file `target + ".tmp"` renamed onto it.
struct WriteTarget
{
  std::string target;
  std::string temporary;  ///< "" when the target is written directly (a device, a FIFO)
};
WriteTarget writeTargetFor(const std::string& path);

/// "<errno text>", plus a hint for a missing folder ("the folder `d` does not exist").
std::string osReason(int err, const std::string& path);

class CheckedFileWriter
{
public:
  /// Creates the (temporary) file; throws WriteError naming `path` (missing folder, permission).
  explicit CheckedFileWriter(const std::string& path);
  /// Without commit(): discards the temporary file (the destination is left as it was). Never throws.
  ~CheckedFileWriter();
  CheckedFileWriter(const CheckedFileWriter&) = delete;
  CheckedFileWriter& operator=(const CheckedFileWriter&) = delete;

  /// A buffered std::ostream over the file. A failed write sets the stream's badbit; the OS
  /// reason is kept and thrown by the next write() or by commit().
  std::ostream& stream();
  /// Appends bytes; throws WriteError at once when the file cannot take them.
  void write(const void* data, size_t size);
  void write(const std::string& bytes) { write(bytes.data(), bytes.size()); }
  /// Flushes, closes and renames the temporary file onto the path; throws WriteError naming the
  /// path and the reason for any failure of the writes, the flush, the close or the rename.
  void commit();
  const std::string& path() const { return path_; }
  /// Bytes written so far.
  uint64_t bytes() const;

private:
  class Buffer;
  [[noreturn]] void fail(const std::string& what, int err);
  void discard() noexcept;
  std::string path_;
  WriteTarget target_;
  std::unique_ptr<Buffer> buf_;
  std::unique_ptr<std::ostream> stream_;
  bool done_ = false;
};

/// Writes `bytes` to `path` (checked as above).
void writeFileChecked(const std::string& path, const std::string& bytes);
/// Writes what `fill` puts into the stream to `path` (checked as above). An exception thrown by
/// `fill` leaves the destination untouched and propagates.
void writeFileChecked(const std::string& path, const std::function<void(std::ostream&)>& fill);
}  // namespace dvs_driver
