#include <dvs_driver/formats/compression.h>
#include <dvs_driver/formats/event_format.h>

#include <lz4frame.h>
#include <zstd.h>

#include <cstring>

namespace dvs_driver
{
namespace formats
{
void ByteBuffer::reserve(size_t n)
{
  if (n <= capacity)
    return;
  size_t c = capacity ? capacity : 4096;
  while (c < n)
    c *= 2;
  std::unique_ptr<uint8_t[]> d(new uint8_t[c]);
  if (size)
    std::memcpy(d.get(), data.get(), size);
  data = std::move(d);
  capacity = c;
}

Decompressor::Decompressor() = default;

Decompressor::~Decompressor()
{
  if (lz4_)
    LZ4F_freeDecompressionContext(static_cast<LZ4F_dctx*>(lz4_));
  if (zstd_)
    ZSTD_freeDCtx(static_cast<ZSTD_DCtx*>(zstd_));
}

std::string Decompressor::lz4(const uint8_t* src, size_t n, ByteBuffer& out)
{
  if (!lz4_)
  {
    LZ4F_dctx* ctx = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
      return "cannot create an LZ4 context";
    lz4_ = ctx;
  }
  auto* ctx = static_cast<LZ4F_dctx*>(lz4_);
  LZ4F_resetDecompressionContext(ctx);
  out.size = 0;
  out.reserve(std::max<size_t>(n * 4, 1 << 16));
  size_t in = 0;
  for (;;)
  {
    if (out.size == out.capacity)
      out.reserve(out.capacity * 2);
    size_t dst = out.capacity - out.size, srcn = n - in;
    const size_t r = LZ4F_decompress(ctx, out.data.get() + out.size, &dst, src + in, &srcn, nullptr);
    if (LZ4F_isError(r))
      return std::string("LZ4 frame error: ") + LZ4F_getErrorName(r);
    out.size += dst;
    in += srcn;
    if (r == 0)
      return "";  // frame complete
    if (in == n && dst == 0)
      return "LZ4 frame ends early";
  }
}

std::string Decompressor::zstd(const uint8_t* src, size_t n, ByteBuffer& out)
{
  if (!zstd_)
  {
    zstd_ = ZSTD_createDCtx();
    if (!zstd_)
      return "cannot create a zstd context";
  }
  auto* ctx = static_cast<ZSTD_DCtx*>(zstd_);
  ZSTD_DCtx_reset(ctx, ZSTD_reset_session_only);
  out.size = 0;
  out.reserve(std::max<size_t>(n * 4, 1 << 16));
  ZSTD_inBuffer in{src, n, 0};
  for (;;)
  {
    if (out.size == out.capacity)
      out.reserve(out.capacity * 2);
    ZSTD_outBuffer o{out.data.get() + out.size, out.capacity - out.size, 0};
    const size_t r = ZSTD_decompressStream(ctx, &o, &in);
    if (ZSTD_isError(r))
      return std::string("zstd error: ") + ZSTD_getErrorName(r);
    out.size += o.pos;
    if (r == 0)
      return "";  // frame complete
    if (in.pos == in.size && o.pos < o.size)
      return "zstd frame ends early";
  }
}

void lz4Compress(const uint8_t* src, size_t n, std::vector<uint8_t>& out, int level)
{
  LZ4F_preferences_t prefs;
  std::memset(&prefs, 0, sizeof prefs);
  prefs.frameInfo.blockSizeID = LZ4F_max64KB;
  prefs.frameInfo.blockMode = LZ4F_blockLinked;
  prefs.compressionLevel = level;
  out.resize(LZ4F_compressFrameBound(n, &prefs));
  const size_t r = LZ4F_compressFrame(out.data(), out.size(), src, n, &prefs);
  if (LZ4F_isError(r))
    throw EventFormatError(std::string("LZ4 compression failed: ") + LZ4F_getErrorName(r));
  out.resize(r);
}

void zstdCompress(const uint8_t* src, size_t n, std::vector<uint8_t>& out, int level)
{
  out.resize(ZSTD_compressBound(n));
  const size_t r = ZSTD_compress(out.data(), out.size(), src, n, level);
  if (ZSTD_isError(r))
    throw EventFormatError(std::string("zstd compression failed: ") + ZSTD_getErrorName(r));
  out.resize(r);
}
}  // namespace formats
}  // namespace dvs_driver
