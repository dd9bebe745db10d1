#pragma once
// LZ4 frame and zstd (de)compression of whole buffers with reusable contexts (ROS-free).
// LZ4 payloads are LZ4 *frames* (possibly several linked blocks), decoded with LZ4F_decompress.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dvs_driver
{
namespace formats
{
/// A growable byte buffer that is not zero-filled on growth.
struct ByteBuffer
{
  std::unique_ptr<uint8_t[]> data;
  size_t size = 0, capacity = 0;
  void reserve(size_t n);
};

class Decompressor
{
public:
  Decompressor();
  ~Decompressor();
  Decompressor(const Decompressor&) = delete;
  Decompressor& operator=(const Decompressor&) = delete;
  /// Decompress one LZ4 frame / one zstd frame into out (replacing its contents). Returns "" or
  /// an error text.
  std::string lz4(const uint8_t* src, size_t n, ByteBuffer& out);
  std::string zstd(const uint8_t* src, size_t n, ByteBuffer& out);

private:
  void* lz4_ = nullptr;   // LZ4F_dctx*
  void* zstd_ = nullptr;  // ZSTD_DCtx*
};

/// One LZ4 frame (64 KB linked blocks, as DV writes) at `level` (0 = fast, >= 3 = HC).
void lz4Compress(const uint8_t* src, size_t n, std::vector<uint8_t>& out, int level = 0);
/// One zstd frame at `level`.
void zstdCompress(const uint8_t* src, size_t n, std::vector<uint8_t>& out, int level = 3);
}  // namespace formats
}  // namespace dvs_driver
