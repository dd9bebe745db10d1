// Writer of HDF5 event files (flat or DSEC layout, optionally gzip / blosc); see
// formats/hdf5_events.h.
#include <dvs_driver/formats/hdf5_events.h>

#include "hdf5_handle.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace dvs_driver
{
namespace formats
{
using hdf5::Handle;

struct Hdf5Writer::Impl
{
  std::string path;
  uint32_t width = 0, height = 0;
  Hdf5WriterOptions opt;
  Handle file, group;
  std::array<Handle, 4> ds;  // x, y, t, p
  std::vector<uint16_t> x, y;
  std::vector<int64_t> t;  // flat: us; DSEC: us relative to t_offset (written as uint32)
  std::vector<uint8_t> p;
  uint64_t written = 0;
  bool have_offset = false;
  int64_t t_offset_us = 0;
  std::vector<uint64_t> ms_to_idx;
  bool closed = false;

  [[noreturn]] void fail(const std::string& what) const
  {
    throw EventFormatError(path + ": HDF5 writer: " + what + (hdf5::lastError().empty() ? "" : " (" + hdf5::lastError() + ")"));
  }

  Handle chunkedPlist() const
  {
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
    const hsize_t chunk = opt.chunk_events;
    H5Pset_chunk(dcpl.get(), 1, &chunk);
    const int level = std::max(1, std::min(9, opt.level));
    if (opt.compression == Hdf5Compression::Gzip)
    {
      H5Pset_shuffle(dcpl.get());
      H5Pset_deflate(dcpl.get(), unsigned(level));
    }
    else if (opt.compression == Hdf5Compression::Blosc)
    {
      // cd_values 0-3 are filled in by the plugin; 4 level, 5 shuffle (1 = byte), 6 compressor
      // (5 = BLOSC_ZSTD, as in DSEC's files).
      const unsigned cd[7] = {0, 0, 0, 0, unsigned(level), 1, 5};
      if (H5Pset_filter(dcpl.get(), hdf5::kBloscFilter, H5Z_FLAG_MANDATORY, 7, cd) < 0)
        fail("cannot set the blosc filter");
    }
    return dcpl;
  }

  Handle create(hid_t loc, const char* name, hid_t type, hsize_t n0, hsize_t maxn, const Handle& dcpl)
  {
    Handle space(H5Screate_simple(1, &n0, &maxn));
    Handle d(H5Dcreate2(loc, name, type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT));
    if (!d)
      fail(std::string("cannot create dataset ") + name);
    return d;
  }

  void writeAttribute(hid_t loc, const char* name, uint32_t v)
  {
    Handle space(H5Screate(H5S_SCALAR));
    Handle a(H5Acreate2(loc, name, H5T_STD_U32LE, space.get(), H5P_DEFAULT, H5P_DEFAULT));
    if (!a || H5Awrite(a.get(), H5T_NATIVE_UINT32, &v) < 0)
      fail(std::string("cannot write attribute ") + name);
  }

  void append(const Handle& d, hid_t memtype, const void* data, hsize_t k)
  {
    const hsize_t start = written, total = written + k;
    if (H5Dset_extent(d.get(), &total) < 0)
      fail("cannot extend a dataset");
    Handle fs(H5Dget_space(d.get()));
    Handle ms(H5Screate_simple(1, &k, nullptr));
    if (H5Sselect_hyperslab(fs.get(), H5S_SELECT_SET, &start, nullptr, &k, nullptr) < 0 ||
        H5Dwrite(d.get(), memtype, ms.get(), fs.get(), H5P_DEFAULT, data) < 0)
      fail("cannot write events");
  }

  void flush()
  {
    const hsize_t k = x.size();
    if (k == 0)
      return;
    append(ds[0], H5T_NATIVE_UINT16, x.data(), k);
    append(ds[1], H5T_NATIVE_UINT16, y.data(), k);
    append(ds[2], H5T_NATIVE_INT64, t.data(), k);
    append(ds[3], H5T_NATIVE_UINT8, p.data(), k);
    written += k;
    x.clear();
    y.clear();
    t.clear();
    p.clear();
  }
};

Hdf5Writer::Hdf5Writer(const std::string& path, uint32_t width, uint32_t height, Hdf5WriterOptions options)
  : impl_(std::make_unique<Impl>())
{
  Impl& m = *impl_;
  m.path = path;
  m.width = width;
  m.height = height;
  m.opt = options;
  if (m.opt.chunk_events == 0)
    m.opt.chunk_events = 65536;
  hdf5::Quiet quiet;
  if (m.opt.compression == Hdf5Compression::Blosc && H5Zfilter_avail(hdf5::kBloscFilter) <= 0)
    m.fail("the blosc filter (HDF5 filter 32001) is not available: install hdf5-filter-plugin-blosc-serial or set "
           "HDF5_PLUGIN_PATH");
  m.file = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  if (!m.file)
    m.fail("cannot create the file");
  m.writeAttribute(m.file.get(), "width", width);
  m.writeAttribute(m.file.get(), "height", height);
  hid_t loc = m.file.get();
  if (m.opt.layout == Hdf5Layout::Dsec)
  {
    m.group = Handle(H5Gcreate2(m.file.get(), "events", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    if (!m.group)
      m.fail("cannot create group /events");
    loc = m.group.get();
  }
  const Handle dcpl = m.chunkedPlist();
  const bool dsec = m.opt.layout == Hdf5Layout::Dsec;
  m.ds[0] = m.create(loc, "x", H5T_STD_U16LE, 0, H5S_UNLIMITED, dcpl);
  m.ds[1] = m.create(loc, "y", H5T_STD_U16LE, 0, H5S_UNLIMITED, dcpl);
  m.ds[2] = m.create(loc, "t", dsec ? H5T_STD_U32LE : H5T_STD_I64LE, 0, H5S_UNLIMITED, dcpl);
  m.ds[3] = m.create(loc, "p", H5T_STD_U8LE, 0, H5S_UNLIMITED, dcpl);
  m.x.reserve(m.opt.chunk_events);
  m.y.reserve(m.opt.chunk_events);
  m.t.reserve(m.opt.chunk_events);
  m.p.reserve(m.opt.chunk_events);
}

Hdf5Writer::~Hdf5Writer()
{
  try
  {
    close();
  }
  catch (...)
  {
  }
}

uint64_t Hdf5Writer::eventsWritten() const
{
  return impl_->written + impl_->x.size();
}

void Hdf5Writer::write(const Event* events, size_t n)
{
  Impl& m = *impl_;
  if (m.closed)
    m.fail("write after close");
  hdf5::Quiet quiet;
  const bool dsec = m.opt.layout == Hdf5Layout::Dsec;
  for (const Event* ev = events; ev != events + n; ++ev)
  {
    const Event& e = *ev;
    int64_t us = e.t_ns / 1000;
    if (e.t_ns < 0 && us * 1000 != e.t_ns)
      --us;  // round down
    if (dsec)
    {
      if (!m.have_offset)
      {
        m.have_offset = true;
        m.t_offset_us = us;
      }
      us -= m.t_offset_us;
      if (us < 0 || us > int64_t(UINT32_MAX))
        m.fail("event time " + std::to_string(us + m.t_offset_us) + " us is " +
               (us < 0 ? "before the first event's (DSEC t_offset)" : "more than 2^32 us after the first event") +
               ": it does not fit the DSEC layout's uint32 t");
      const uint64_t index = m.written + m.x.size();
      while (uint64_t(m.ms_to_idx.size()) * 1000 <= uint64_t(us))
        m.ms_to_idx.push_back(index);
    }
    m.x.push_back(e.x);
    m.y.push_back(e.y);
    m.t.push_back(us);
    m.p.push_back(e.polarity ? 1 : 0);
    if (m.x.size() >= m.opt.chunk_events)
      m.flush();
  }
}

void Hdf5Writer::close()
{
  Impl& m = *impl_;
  if (m.closed)
    return;
  m.closed = true;
  hdf5::Quiet quiet;
  m.flush();
  if (m.opt.layout == Hdf5Layout::Dsec)
  {
    Handle plain(H5Pcreate(H5P_DATASET_CREATE));
    Handle space(H5Screate(H5S_SCALAR));
    Handle off(H5Dcreate2(m.file.get(), "t_offset", H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    if (!off || H5Dwrite(off.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &m.t_offset_us) < 0)
      m.fail("cannot write /t_offset");
    const hsize_t n = m.ms_to_idx.size();
    Handle s(H5Screate_simple(1, &n, nullptr));
    Handle idx(H5Dcreate2(m.file.get(), "ms_to_idx", H5T_STD_U64LE, s.get(), H5P_DEFAULT, plain.get(), H5P_DEFAULT));
    if (!idx || (n > 0 && H5Dwrite(idx.get(), H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.ms_to_idx.data()) < 0))
      m.fail("cannot write /ms_to_idx");
  }
  for (auto& d : m.ds)
    d.reset();
  m.group.reset();
  if (H5Fflush(m.file.get(), H5F_SCOPE_GLOBAL) < 0)
    m.fail("cannot flush the file");
  m.file.reset();
}
}  // namespace formats
}  // namespace dvs_driver
