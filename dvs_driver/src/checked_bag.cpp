#include <dvs_driver/checked_bag.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace dvs_driver
{
CheckedBagWriter::CheckedBagWriter(const std::string& path) : path_(path)
{
  if (path.empty())
    throw BagWriteError("(empty path)", "cannot write a bag: no file name given");
  target_ = writeTargetFor(path);
  if (!target_.temporary.empty())
    file_ = target_.temporary;
  else
  {
    // Not a regular file (a device, a FIFO): the bag is finished in a temporary file first.
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/dvs_bag_XXXXXX";
    std::vector<char> name(tmpl.begin(), tmpl.end());
    name.push_back('\0');
    const int fd = ::mkstemp(name.data());
    if (fd < 0)
    {
      const int err = errno;
      throw BagWriteError(path, "cannot create a temporary bag in " + tmpl + ": " + std::strerror(err));
    }
    ::close(fd);
    file_ = name.data();
  }
  bag_.reset(new rosbag::Bag);
  errno = 0;
  try
  {
    bag_->open(file_, rosbag::bagmode::Write);
  }
  catch (const rosbag::BagException& e)
  {
    const int err = errno;
    abandon();  // may be half open: rosbag's destructor would retry the failed write
    throw BagWriteError(path, std::string("cannot create the bag: ") + e.what() +
                                  (err != 0 ? " (" + osReason(err, file_) + ")" : std::string()));
  }
}

CheckedBagWriter::~CheckedBagWriter()
{
  if (!bag_)
    return;
  // Not closed (an exception on the way): close quietly, then discard.
  try
  {
    bag_->close();
  }
  catch (...)
  {
    (void)bag_.release();  // see abandon()
  }
  bag_.reset();
  ::unlink(file_.c_str());
}

void CheckedBagWriter::abandon() noexcept
{
  // rosbag::Bag::~Bag() calls close(), which retries the writes that failed and throws from the
  // destructor (std::terminate), or touches a FILE* that a failed fclose() already freed. The
  // object is therefore leaked on purpose (a few KB and a file descriptor, once per failure).
  (void)bag_.release();
  ::unlink(file_.c_str());
}

void CheckedBagWriter::fail(const std::string& what, const std::string& rosbag_message, int err)
{
  abandon();
  std::string reason = rosbag_message;
  if (err != 0)
    reason += " (" + std::string(std::strerror(err)) + ")";
  throw BagWriteError(path_, what + ": " + reason);
}

void CheckedBagWriter::close()
{
  if (!bag_)
    throw BagWriteError(path_, "closed twice or after a failure");
  errno = 0;
  try
  {
    bag_->close();
  }
  catch (const rosbag::BagException& e)
  {
    fail("finishing the bag failed", e.what(), errno);
  }
  bag_.reset();
  if (!target_.temporary.empty())
  {
    if (::rename(file_.c_str(), target_.target.c_str()) != 0)
    {
      const int err = errno;
      ::unlink(file_.c_str());
      throw BagWriteError(path_, "cannot rename " + file_ + " onto it: " + osReason(err, path_));
    }
    return;
  }
  // A device or FIFO: copy the finished bag into it, checked.
  try
  {
    std::ifstream in(file_, std::ios::binary);
    if (!in)
      throw BagWriteError(path_, "cannot reopen the temporary bag " + file_);
    CheckedFileWriter out(path_);
    std::vector<char> block(1 << 16);
    while (in)
    {
      in.read(block.data(), static_cast<std::streamsize>(block.size()));
      if (in.gcount() > 0)
        out.write(block.data(), static_cast<size_t>(in.gcount()));
    }
    if (in.bad())
      throw BagWriteError(path_, "cannot read back the temporary bag " + file_);
    out.commit();
  }
  catch (const WriteError& e)
  {
    ::unlink(file_.c_str());
    std::string m = e.what();
    const std::string prefix = e.path() + ": ";
    if (m.compare(0, prefix.size(), prefix) == 0)
      m.erase(0, prefix.size());
    throw BagWriteError(path_, m);
  }
  ::unlink(file_.c_str());
}
}  // namespace dvs_driver
