// Streaming reader of HDF5 event files (DSEC and flat layouts); see formats/hdf5_events.h.
#include <dvs_driver/formats/hdf5_events.h>

#include "hdf5_handle.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <vector>

namespace dvs_driver
{
namespace formats
{
namespace hdf5
{
std::string lastError()
{
  std::string msg;
  auto walk = [](unsigned n, const H5E_error2_t* e, void* data) -> herr_t {
    auto* out = static_cast<std::string*>(data);
    (void)n;
    if (e->desc)
      *out = e->desc;  // walking downwards: the last one is the innermost cause
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk, &msg);
  return msg;
}
}  // namespace hdf5

namespace
{
using hdf5::Handle;

bool linkExists(hid_t loc, const std::string& name)
{
  return H5Lexists(loc, name.c_str(), H5P_DEFAULT) > 0;
}

std::string rootMembers(hid_t file)
{
  std::string names;
  auto add = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    auto* s = static_cast<std::string*>(data);
    if (s->size() > 200)
      return 1;
    *s += (s->empty() ? "" : ", ") + std::string(name);
    return 0;
  };
  H5Literate(file, H5_INDEX_NAME, H5_ITER_INC, nullptr, add, &names);
  return names.empty() ? "nothing" : names;
}

/// Reads an unsigned integer attribute `name` of `loc` if there is one.
bool readUintAttribute(hid_t loc, const char* name, uint32_t& value)
{
  if (H5Aexists(loc, name) <= 0)
    return false;
  Handle a(H5Aopen(loc, name, H5P_DEFAULT));
  if (!a)
    return false;
  Handle type(H5Aget_type(a.get()));
  Handle space(H5Aget_space(a.get()));
  if (H5Tget_class(type.get()) != H5T_INTEGER || H5Sget_simple_extent_npoints(space.get()) != 1)
    return false;
  uint64_t v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_UINT64, &v) < 0 || v > 65536)
    return false;
  value = uint32_t(v);
  return true;
}

const char* filterName(H5Z_filter_t id)
{
  switch (id)
  {
    case H5Z_FILTER_DEFLATE:
      return "gzip";
    case H5Z_FILTER_SHUFFLE:
      return "shuffle";
    case H5Z_FILTER_FLETCHER32:
      return "fletcher32";
    case H5Z_FILTER_SZIP:
      return "szip";
    case hdf5::kBloscFilter:
      return "blosc";
    case 32015:
      return "zstd";
    case 36559:
      return "Prophesee ECF";
    default:
      return "unregistered";
  }
}

class Hdf5Reader : public EventFileReader
{
public:
  explicit Hdf5Reader(const std::string& path) : path_(path)
  {
    hdf5::Quiet quiet;
    struct stat st
    {
    };
    if (::stat(path.c_str(), &st) == 0)
      stats_.file_size = uint64_t(st.st_size);
    if (H5Fis_hdf5(path.c_str()) <= 0)
      fail("not a readable HDF5 file (truncated or corrupt: " + hdf5::lastError() + ")");
    file_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
    if (!file_)
      fail("not a readable HDF5 file (truncated or corrupt: " + hdf5::lastError() + ")");

    static const std::array<const char*, 4> kNames = {"x", "y", "t", "p"};
    auto hasAll = [&](const std::string& prefix) {
      for (const char* n : kNames)
        if (!linkExists(file_.get(), prefix + n))
          return false;
      return true;
    };
    std::string prefix;
    if (linkExists(file_.get(), "events") && hasAll("events/"))
    {
      dsec_ = true;
      prefix = "events/";
    }
    else if (!hasAll(""))
    {
      std::string hint;
      if (linkExists(file_.get(), "CD"))
        hint = " (Prophesee HDF5 /CD/events with its ECF codec is not supported)";
      fail("unsupported HDF5 event layout: neither /events/{x,y,t,p} (DSEC) nor /{x,y,t,p} (flat); the root "
           "holds " + rootMembers(file_.get()) + hint);
    }
    for (size_t i = 0; i < 4; ++i)
      openField(i, prefix + kNames[i]);
    n_ = fields_[0].n;
    for (size_t i = 1; i < 4; ++i)
      if (fields_[i].n != n_)
        fail("datasets /" + prefix + "x and /" + fields_[i].name + " have different lengths (" + std::to_string(n_) +
             " and " + std::to_string(fields_[i].n) + ")");

    if (dsec_)
    {
      width_ = 640;
      height_ = 480;
      if (linkExists(file_.get(), "t_offset"))
        t_offset_us_ = readScalarInt64("t_offset");
      Handle events(H5Gopen2(file_.get(), "events", H5P_DEFAULT));
      uint32_t w = 0, h = 0;
      if ((readUintAttribute(file_.get(), "width", w) && readUintAttribute(file_.get(), "height", h)) ||
          (events && readUintAttribute(events.get(), "width", w) && readUintAttribute(events.get(), "height", h)))
      {
        width_ = w;
        height_ = h;
      }
    }
    else
    {
      uint32_t w = 0, h = 0;
      if (readUintAttribute(file_.get(), "width", w) && readUintAttribute(file_.get(), "height", h))
      {
        width_ = w;
        height_ = h;
      }
    }
    x_.resize(kChunk);
    y_.resize(kChunk);
    t_.resize(kChunk);
    p_.resize(kChunk);
  }

  bool read(EventVector& out, size_t max_events) override
  {
    hdf5::Quiet quiet;
    size_t appended = 0;
    while (appended < max_events && pos_ < n_)
    {
      const hsize_t k = std::min<hsize_t>({hsize_t(max_events - appended), kChunk, n_ - pos_});
      const bool ok = readSlab(0, H5T_NATIVE_INT32, x_.data(), k) && readSlab(1, H5T_NATIVE_INT32, y_.data(), k) &&
                      readSlab(2, H5T_NATIVE_INT64, t_.data(), k) && readSlab(3, H5T_NATIVE_INT32, p_.data(), k);
      if (!ok)
      {
        ++stats_.damaged_packets;
        warn("damaged: events " + std::to_string(pos_) + ".." + std::to_string(pos_ + k - 1) +
             " could not be read (" + hdf5::lastError() + "), skipped");
        pos_ += k;
        continue;
      }
      const size_t before = out.size();
      for (hsize_t i = 0; i < k; ++i)
      {
        const int32_t x = x_[i], y = y_[i];
        if (x < 0 || y < 0 || x > 65535 || y > 65535 || (width_ && uint32_t(x) >= width_) ||
            (height_ && uint32_t(y) >= height_))
        {
          ++stats_.out_of_range;
          continue;
        }
        Event e;
        e.t_ns = (t_[i] + t_offset_us_) * 1000;
        e.x = uint16_t(x);
        e.y = uint16_t(y);
        e.polarity = p_[i] > 0;
        out.push_back(e);
      }
      appended += out.size() - before;
      stats_.events += out.size() - before;
      pos_ += k;
      stats_.bytes_read = n_ ? uint64_t(double(stats_.file_size) * double(pos_) / double(n_)) : stats_.file_size;
    }
    if (pos_ >= n_)
      stats_.bytes_read = stats_.file_size;
    return appended > 0;
  }

  uint32_t width() const override { return width_; }
  uint32_t height() const override { return height_; }
  std::string formatName() const override { return dsec_ ? "HDF5 (DSEC layout)" : "HDF5 (flat x/y/t/p)"; }
  ReaderStats stats() const override { return stats_; }
  int64_t expectedEvents() const override { return int64_t(n_); }

private:
  static constexpr hsize_t kChunk = 65536;

  struct Field
  {
    Handle ds, space;
    std::string name;
    hsize_t n = 0;
  };

  [[noreturn]] void fail(const std::string& what) const { throw EventFormatError(path_ + ": " + what); }

  void warn(const std::string& text)
  {
    const std::string kind = text.substr(0, text.find(':'));
    for (const auto& w : stats_.warnings)
      if (w.compare(0, kind.size(), kind) == 0)
        return;
    stats_.warnings.push_back(text);
  }

  void openField(size_t i, const std::string& name)
  {
    Field& f = fields_[i];
    f.name = name;
    f.ds = Handle(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT));
    if (!f.ds)
      fail("/" + name + " is not a dataset");
    f.space = Handle(H5Dget_space(f.ds.get()));
    Handle type(H5Dget_type(f.ds.get()));
    if (H5Sget_simple_extent_ndims(f.space.get()) != 1)
      fail("/" + name + " is not a 1-D dataset");
    if (H5Tget_class(type.get()) != H5T_INTEGER)
      fail("/" + name + " is not an integer dataset (only integer x, y, t (us), p are supported)");
    H5Sget_simple_extent_dims(f.space.get(), &f.n, nullptr);
    Handle dcpl(H5Dget_create_plist(f.ds.get()));
    const int nf = H5Pget_nfilters(dcpl.get());
    for (int k = 0; k < nf; ++k)
    {
      unsigned flags = 0;
      size_t nelem = 0;
      const H5Z_filter_t id = H5Pget_filter2(dcpl.get(), unsigned(k), &flags, &nelem, nullptr, 0, nullptr, nullptr);
      if (id >= 0 && H5Zfilter_avail(id) <= 0)
        fail("/" + name + " is compressed with HDF5 filter " + std::to_string(id) + " (" + filterName(id) +
             "), which is not available" +
             (id == hdf5::kBloscFilter ? ": install hdf5-filter-plugin-blosc-serial or set HDF5_PLUGIN_PATH" : ""));
    }
  }

  int64_t readScalarInt64(const char* name)
  {
    Handle ds(H5Dopen2(file_.get(), name, H5P_DEFAULT));
    Handle space(ds ? H5Dget_space(ds.get()) : H5I_INVALID_HID);
    Handle type(ds ? H5Dget_type(ds.get()) : H5I_INVALID_HID);
    int64_t v = 0;
    if (!ds || H5Tget_class(type.get()) != H5T_INTEGER || H5Sget_simple_extent_npoints(space.get()) != 1 ||
        H5Dread(ds.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &v) < 0)
      fail(std::string("/") + name + " is not a readable integer scalar");
    return v;
  }

  bool readSlab(size_t i, hid_t memtype, void* buf, hsize_t k)
  {
    Field& f = fields_[i];
    const hsize_t start = pos_;
    if (H5Sselect_hyperslab(f.space.get(), H5S_SELECT_SET, &start, nullptr, &k, nullptr) < 0)
      return false;
    Handle mem(H5Screate_simple(1, &k, nullptr));
    return H5Dread(f.ds.get(), memtype, mem.get(), f.space.get(), H5P_DEFAULT, buf) >= 0;
  }

  std::string path_;
  Handle file_;
  std::array<Field, 4> fields_;
  bool dsec_ = false;
  hsize_t n_ = 0, pos_ = 0;
  int64_t t_offset_us_ = 0;
  uint32_t width_ = 0, height_ = 0;
  std::vector<int32_t> x_, y_, p_;
  std::vector<int64_t> t_;
  ReaderStats stats_;
};
}  // namespace

std::unique_ptr<EventFileReader> openHdf5Events(const std::string& path)
{
  return std::make_unique<Hdf5Reader>(path);
}
}  // namespace formats
}  // namespace dvs_driver
