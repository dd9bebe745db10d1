#include <dvs_driver/checked_write.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <streambuf>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace dvs_driver
{
namespace
{
std::string folderOf(const std::string& path)
{
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos)
    return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}
}  // namespace

std::string osReason(int err, const std::string& path)
{
  std::string r = std::strerror(err);
  if (err == ENOENT || err == ENOTDIR)
  {
    struct stat st;
    const std::string dir = folderOf(path);
    if (::stat(dir.c_str(), &st) != 0)
      r += " (the folder `" + dir + "` does not exist)";
    else if (!S_ISDIR(st.st_mode))
      r += " (`" + dir + "` is not a folder)";
  }
  return r;
}

WriteTarget writeTargetFor(const std::string& path)
{
  WriteTarget t;
  t.target = path;
  struct stat st;
  if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode))
  {
    char resolved[PATH_MAX];
    if (::realpath(path.c_str(), resolved))
      t.target = resolved;
  }
  if (::stat(t.target.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    return t;  // a device, a FIFO, ... (a folder fails at open, naming it)
  t.temporary = t.target + ".tmp";
  return t;
}

// A streambuf over a file descriptor that remembers the first OS error.
class CheckedFileWriter::Buffer : public std::streambuf
{
public:
  explicit Buffer(int fd) : fd_(fd), data_(1 << 16)
  {
    setp(data_.data(), data_.data() + data_.size());
  }
  ~Buffer() override
  {
    if (fd_ >= 0)
      ::close(fd_);
  }
  int error() const { return error_; }
  uint64_t bytes() const { return bytes_ + static_cast<uint64_t>(pptr() - pbase()); }

  /// Writes the buffered bytes; false (error() set) on failure.
  bool drain()
  {
    const char* p = pbase();
    size_t left = static_cast<size_t>(pptr() - pbase());
    while (left > 0 && error_ == 0)
    {
      const ssize_t n = ::write(fd_, p, left);
      if (n < 0)
      {
        if (errno == EINTR)
          continue;
        error_ = errno;
        break;
      }
      if (n == 0)
      {
        error_ = EIO;
        break;
      }
      p += n;
      left -= static_cast<size_t>(n);
      bytes_ += static_cast<uint64_t>(n);
    }
    setp(data_.data(), data_.data() + data_.size());
    return error_ == 0;
  }

  /// Closes the descriptor; false (error() set) on failure.
  bool closeFd()
  {
    if (fd_ < 0)
      return error_ == 0;
    const int r = ::close(fd_);
    fd_ = -1;
    if (r != 0 && error_ == 0)
      error_ = errno;
    return error_ == 0;
  }

protected:
  int_type overflow(int_type c) override
  {
    if (error_ != 0 || !drain())
      return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof()))
    {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

private:
  int fd_;
  std::vector<char> data_;
  int error_ = 0;
  uint64_t bytes_ = 0;
};

CheckedFileWriter::CheckedFileWriter(const std::string& path) : path_(path)
{
  if (path.empty())
    throw WriteError("(empty path)", "cannot write: no file name given");
  target_ = writeTargetFor(path);
  const std::string& open_path = target_.temporary.empty() ? target_.target : target_.temporary;
  const int flags = O_WRONLY | O_CLOEXEC | (target_.temporary.empty() ? 0 : (O_CREAT | O_TRUNC));
  int fd;
  do
    fd = ::open(open_path.c_str(), flags, 0666);
  while (fd < 0 && errno == EINTR);
  if (fd < 0 && !target_.temporary.empty() && (errno == EACCES || errno == EPERM || errno == EROFS) &&
      ::access(target_.target.c_str(), W_OK) == 0)
  {
    // A writable file in a folder where no temporary file can be made: written in place.
    target_.temporary.clear();
    do
      fd = ::open(target_.target.c_str(), O_WRONLY | O_CLOEXEC | O_TRUNC);
    while (fd < 0 && errno == EINTR);
  }
  if (fd < 0)
  {
    const int err = errno;
    throw WriteError(path, "cannot create the file: " + osReason(err, open_path));
  }
  buf_.reset(new Buffer(fd));
  stream_.reset(new std::ostream(buf_.get()));
}

CheckedFileWriter::~CheckedFileWriter()
{
  if (!done_)
    discard();
}

void CheckedFileWriter::discard() noexcept
{
  done_ = true;
  stream_.reset();
  buf_.reset();  // closes
  if (!target_.temporary.empty())
    ::unlink(target_.temporary.c_str());
}

void CheckedFileWriter::fail(const std::string& what, int err)
{
  discard();
  throw WriteError(path_, what + ": " + osReason(err, path_));
}

std::ostream& CheckedFileWriter::stream()
{
  if (done_)
    throw WriteError(path_, "written to after commit");
  return *stream_;
}

void CheckedFileWriter::write(const void* data, size_t size)
{
  if (done_)
    throw WriteError(path_, "written to after commit");
  stream_->write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (buf_->error() != 0)
    fail("write failed", buf_->error());
  if (!*stream_)
    fail("write failed", EIO);
}

uint64_t CheckedFileWriter::bytes() const
{
  return buf_ ? buf_->bytes() : 0;
}

void CheckedFileWriter::commit()
{
  if (done_)
    throw WriteError(path_, "committed twice");
  stream_->flush();
  if (buf_->error() != 0)
    fail("write failed", buf_->error());
  if (!*stream_)
    fail("write failed (stream error)", EIO);
  if (!buf_->closeFd())
    fail("closing the file failed", buf_->error());
  if (!target_.temporary.empty() && ::rename(target_.temporary.c_str(), target_.target.c_str()) != 0)
  {
    const int err = errno;
    fail("cannot rename " + target_.temporary + " onto it", err);
  }
  done_ = true;
  stream_.reset();
  buf_.reset();
}

void writeFileChecked(const std::string& path, const std::string& bytes)
{
  CheckedFileWriter w(path);
  w.write(bytes);
  w.commit();
}

void writeFileChecked(const std::string& path, const std::function<void(std::ostream&)>& fill)
{
  CheckedFileWriter w(path);
  fill(w.stream());
  w.commit();
}
}  // namespace dvs_driver
