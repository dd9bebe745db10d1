#pragma once
// Bounds-checked read access to a flatbuffer (vtables, offsets) without generated code; just
// what the AEDAT 4.0 IOHeader, event packets and data table need. Internal to the readers.
#include <dvs_driver/formats/chunked_file.h>

#include <cstdint>
#include <string>

namespace dvs_driver
{
namespace formats
{
class FlatTable
{
public:
  /// The root table of the flatbuffer `buf` (size `size`); valid() is false if out of bounds.
  static FlatTable root(const uint8_t* buf, size_t size)
  {
    if (size < 8)
      return FlatTable();
    return at(buf, size, loadLE<uint32_t>(buf));
  }
  /// The table at byte `pos` of `buf`.
  static FlatTable at(const uint8_t* buf, size_t size, uint64_t pos)
  {
    FlatTable t;
    if (pos + 4 > size)
      return t;
    const int64_t vt = int64_t(pos) - loadLE<int32_t>(buf + pos);
    if (vt < 0 || uint64_t(vt) + 4 > size)
      return t;
    const uint16_t vt_size = loadLE<uint16_t>(buf + vt);
    const uint16_t tbl_size = loadLE<uint16_t>(buf + vt + 2);
    if (vt_size < 4 || (vt_size & 1) || uint64_t(vt) + vt_size > size || pos + tbl_size > size)
      return t;
    t.buf_ = buf;
    t.size_ = size;
    t.pos_ = pos;
    t.vt_ = uint64_t(vt);
    t.fields_ = (vt_size - 4) / 2;
    t.tbl_size_ = tbl_size;
    return t;
  }
  bool valid() const { return buf_ != nullptr; }

  /// Byte position of field `i` (0 if absent).
  uint64_t fieldPos(unsigned i, size_t bytes) const
  {
    if (!valid() || i >= fields_)
      return 0;
    const uint16_t off = loadLE<uint16_t>(buf_ + vt_ + 4 + 2 * i);
    if (off == 0 || off + bytes > tbl_size_)
      return 0;
    return pos_ + off;
  }
  template <typename T>
  T scalar(unsigned i, T def) const
  {
    const uint64_t p = fieldPos(i, sizeof(T));
    return p ? loadLE<T>(buf_ + p) : def;
  }
  /// Target of an offset field (vector, string or table): byte position, or 0 if absent / out
  /// of bounds (a vector or string there starts with its uint32 length).
  uint64_t target(unsigned i) const
  {
    const uint64_t p = fieldPos(i, 4);
    if (!p)
      return 0;
    const uint64_t t = p + loadLE<uint32_t>(buf_ + p);
    return t + 4 <= size_ ? t : 0;
  }
  /// Vector field: element count and the byte position of element 0 (false if absent or the
  /// elements of elem_size bytes do not fit).
  bool vector(unsigned i, size_t elem_size, uint32_t& count, uint64_t& first) const
  {
    const uint64_t t = target(i);
    if (!t)
      return false;
    count = loadLE<uint32_t>(buf_ + t);
    first = t + 4;
    return first + uint64_t(count) * elem_size <= size_;
  }
  bool string(unsigned i, std::string& out) const
  {
    uint32_t n = 0;
    uint64_t first = 0;
    if (!vector(i, 1, n, first))
      return false;
    out.assign(reinterpret_cast<const char*>(buf_ + first), n);
    return true;
  }
  const uint8_t* buffer() const { return buf_; }
  size_t bufferSize() const { return size_; }

private:
  const uint8_t* buf_ = nullptr;
  size_t size_ = 0;
  uint64_t pos_ = 0, vt_ = 0;
  unsigned fields_ = 0;
  uint16_t tbl_size_ = 0;
};
}  // namespace formats
}  // namespace dvs_driver
