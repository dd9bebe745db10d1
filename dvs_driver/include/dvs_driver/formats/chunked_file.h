#pragma once
// A file read in bounded chunks (ROS-free): the byte source of the streaming format readers.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace dvs_driver
{
namespace formats
{
class ChunkedFile
{
public:
  /// Opens `path` for reading; throws EventFormatError naming the file if it cannot.
  explicit ChunkedFile(const std::string& path, size_t chunk_bytes = 1 << 20);
  ~ChunkedFile();
  ChunkedFile(const ChunkedFile&) = delete;
  ChunkedFile& operator=(const ChunkedFile&) = delete;

  const std::string& path() const { return path_; }
  uint64_t size() const { return size_; }

  // Buffered window: bytes [begin(), end()) are the file bytes from offset() on.
  const uint8_t* begin() const { return buf_.get() + pos_; }
  const uint8_t* end() const { return buf_.get() + len_; }
  size_t available() const { return len_ - pos_; }
  uint64_t offset() const { return buf_offset_ + pos_; }
  /// Mark n buffered bytes as consumed.
  void consume(size_t n) { pos_ += n; }
  /// Keep the unconsumed bytes and read more after them; returns false at end of file (nothing
  /// new was read).
  bool refill();

  /// Unbuffered access: read exactly n bytes at the current offset() into dst (consuming them);
  /// returns the number of bytes actually read (< n at end of file).
  size_t read(void* dst, size_t n);
  /// Move the current offset to `off` (drops the buffer).
  void seek(uint64_t off);

private:
  std::string path_;
  std::FILE* f_ = nullptr;
  uint64_t size_ = 0;
  std::unique_ptr<uint8_t[]> buf_;  // not zero-filled
  size_t cap_ = 0;
  size_t chunk_;
  size_t pos_ = 0, len_ = 0;
  uint64_t buf_offset_ = 0;  // file offset of buf_[0]
};

// Little-endian loads (the formats here are all little-endian; x86/ARM compile these to one load).
template <typename T>
inline T loadLE(const uint8_t* p)
{
  T v;
  __builtin_memcpy(&v, p, sizeof(T));
  return v;
}
}  // namespace formats
}  // namespace dvs_driver
