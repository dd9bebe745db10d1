#include <dvs_driver/formats/chunked_file.h>
#include <dvs_driver/formats/event_format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace dvs_driver
{
namespace formats
{
ChunkedFile::ChunkedFile(const std::string& path, size_t chunk_bytes) : path_(path), chunk_(chunk_bytes)
{
  f_ = std::fopen(path.c_str(), "rb");
  if (!f_)
    throw EventFormatError(path + ": cannot open (" + std::strerror(errno) + ")");
  if (std::fseek(f_, 0, SEEK_END) == 0)
  {
    long s = std::ftell(f_);
    size_ = s > 0 ? static_cast<uint64_t>(s) : 0;
  }
  std::fseek(f_, 0, SEEK_SET);
  cap_ = chunk_;
  buf_.reset(new uint8_t[cap_]);
}

ChunkedFile::~ChunkedFile()
{
  if (f_)
    std::fclose(f_);
}

bool ChunkedFile::refill()
{
  const size_t keep = len_ - pos_;
  if (pos_ > 0 && keep > 0)
    std::memmove(buf_.get(), buf_.get() + pos_, keep);
  buf_offset_ += pos_;
  pos_ = 0;
  len_ = keep;
  if (cap_ < keep + chunk_)
  {
    std::unique_ptr<uint8_t[]> bigger(new uint8_t[keep + chunk_]);
    if (keep > 0)  // (memcpy from a null buffer is undefined even for 0 bytes)
      std::memcpy(bigger.get(), buf_.get(), keep);
    buf_ = std::move(bigger);
    cap_ = keep + chunk_;
  }
  const size_t got = std::fread(buf_.get() + len_, 1, cap_ - len_, f_);
  len_ += got;
  return got > 0;
}

size_t ChunkedFile::read(void* dst, size_t n)
{
  uint8_t* d = static_cast<uint8_t*>(dst);
  size_t from_buf = std::min(n, available());
  if (from_buf > 0)  // found by fuzzing: n = 0 with a null destination (an empty vector's data())
    std::memcpy(d, begin(), from_buf);
  pos_ += from_buf;
  size_t got = from_buf;
  if (got < n)
  {
    // Buffer empty: read the rest directly.
    buf_offset_ += pos_;
    pos_ = len_ = 0;
    const size_t direct = std::fread(d + got, 1, n - got, f_);
    buf_offset_ += direct;
    got += direct;
  }
  return got;
}

void ChunkedFile::seek(uint64_t off)
{
  std::fseek(f_, static_cast<long>(off), SEEK_SET);
  buf_offset_ = off;
  pos_ = len_ = 0;
}
}  // namespace formats
}  // namespace dvs_driver
