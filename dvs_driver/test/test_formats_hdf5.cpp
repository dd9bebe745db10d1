// HDF5 event files: round trips through Hdf5Writer (both layouts, every compression), hand-built
// files with known content (DSEC with t_offset, flat with other integer types), damaged files,
// unsupported layouts, and files opened by h5py.
#include <dvs_driver/formats/hdf5_events.h>

#include "formats_test_util.h"

#include <hdf5.h>

#include <cstdlib>
#include <fstream>
#include <random>

using namespace dvs_driver;
using namespace dvs_driver::formats;
using formats_test::TempFile;

namespace
{
EventVector someEvents(size_t n, int64_t t0_us, uint32_t w, uint32_t h, unsigned seed = 1)
{
  std::mt19937 rng(seed);
  EventVector ev(n);
  int64_t t = t0_us;
  for (auto& e : ev)
  {
    t += int64_t(rng() % 40);
    e.t_ns = t * 1000;
    e.x = uint16_t(rng() % w);
    e.y = uint16_t(rng() % h);
    e.polarity = rng() & 1;
  }
  return ev;
}

EventVector readInBatches(EventFileReader& r, size_t batch)
{
  EventVector all, b;
  while (r.read(b, batch))
  {
    EXPECT_LE(b.size(), batch);
    all.insert(all.end(), b.begin(), b.end());
    b.clear();
  }
  return all;
}

// Hand-built datasets through the raw C API.
template <class T>
void dataset(hid_t loc, const char* name, hid_t file_type, hid_t mem_type, const std::vector<T>& v)
{
  const hsize_t n = v.size();
  hid_t space = H5Screate_simple(1, &n, nullptr);
  hid_t d = H5Dcreate2(loc, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(d, 0) << name;
  if (n)
    ASSERT_GE(H5Dwrite(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  H5Dclose(d);
  H5Sclose(space);
}

void scalarI64(hid_t loc, const char* name, int64_t v)
{
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t d = H5Dcreate2(loc, name, H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &v);
  H5Dclose(d);
  H5Sclose(space);
}

void attrU32(hid_t loc, const char* name, uint32_t v)
{
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(loc, name, H5T_STD_U32LE, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_UINT32, &v);
  H5Aclose(a);
  H5Sclose(space);
}

std::string errorOf(const std::string& path)
{
  try
  {
    openEventFileReader(path);
  }
  catch (const EventFormatError& e)
  {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST(FormatsHdf5, RoundTripsExactlyInBothLayoutsAndEveryCompression)
{
  const EventVector ev = someEvents(200000, 1605537493718345, 346, 260);
  for (Hdf5Layout layout : {Hdf5Layout::Flat, Hdf5Layout::Dsec})
    for (Hdf5Compression c : {Hdf5Compression::None, Hdf5Compression::Gzip, Hdf5Compression::Blosc})
    {
      SCOPED_TRACE(int(layout) * 10 + int(c));
      TempFile f(".h5");
      Hdf5WriterOptions o;
      o.layout = layout;
      o.compression = c;
      o.chunk_events = 7777;  // several chunks, a partial last one
      {
        Hdf5Writer w(f.path(), 346, 260, o);
        w.write(ev.data(), 12345);  // in pieces, as convert writes (the state carries over)
        w.write(EventVector(ev.begin() + 12345, ev.end()));
        EXPECT_EQ(w.eventsWritten(), ev.size());
        w.close();
      }
      EXPECT_EQ(detectEventFormat(f.path()), EventFormat::Hdf5);
      auto r = openEventFileReader(f.path());
      EXPECT_EQ(r->formatName(), layout == Hdf5Layout::Dsec ? "HDF5 (DSEC layout)" : "HDF5 (flat x/y/t/p)");
      EXPECT_EQ(r->width(), 346u);
      EXPECT_EQ(r->height(), 260u);
      EXPECT_EQ(r->expectedEvents(), int64_t(ev.size()));
      const EventVector back = readInBatches(*r, 30000);
      ASSERT_EQ(back.size(), ev.size());
      EXPECT_TRUE(back == ev);
      const ReaderStats s = r->stats();
      EXPECT_EQ(s.events, ev.size());
      EXPECT_EQ(s.out_of_range, 0u);
      EXPECT_EQ(s.bytes_read, s.file_size);
      EXPECT_TRUE(s.warnings.empty());
    }
}

TEST(FormatsHdf5, CompressionShrinksTheFile)
{
  const EventVector ev = someEvents(100000, 0, 640, 480);
  TempFile plain(".h5"), blosc(".h5"), gzip(".h5");
  Hdf5WriterOptions o;
  Hdf5Writer(plain.path(), 640, 480, o).write(ev);
  o.compression = Hdf5Compression::Blosc;
  Hdf5Writer(blosc.path(), 640, 480, o).write(ev);
  o.compression = Hdf5Compression::Gzip;
  Hdf5Writer(gzip.path(), 640, 480, o).write(ev);
  const size_t n_plain = formats_test::readBytes(plain.path()).size();
  EXPECT_LT(formats_test::readBytes(blosc.path()).size(), n_plain * 3 / 4);
  EXPECT_LT(formats_test::readBytes(gzip.path()).size(), n_plain * 3 / 4);
}

TEST(FormatsHdf5, DsecWriterTimeOffsetAndMsToIdx)
{
  // times (us): 5000, 5000, 5999, 6000, 8500 -> t_offset 5000, t 0,0,999,1000,3500;
  // ms_to_idx[k] = first index with t >= 1000 k: 0, 3, 4, 4
  EventVector ev;
  for (int64_t us : {5000, 5000, 5999, 6000, 8500})
    ev.push_back(Event{us * 1000, 1, 2, true});
  TempFile f(".h5");
  Hdf5WriterOptions o;
  o.layout = Hdf5Layout::Dsec;
  Hdf5Writer(f.path(), 640, 480, o).write(ev);

  hid_t file = H5Fopen(f.path().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  int64_t off = 0;
  hid_t d = H5Dopen2(file, "t_offset", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &off);
  H5Dclose(d);
  EXPECT_EQ(off, 5000);
  std::vector<uint64_t> idx(4, 99);
  d = H5Dopen2(file, "ms_to_idx", H5P_DEFAULT);
  hid_t space = H5Dget_space(d);
  EXPECT_EQ(H5Sget_simple_extent_npoints(space), 4);
  H5Dread(d, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, idx.data());
  H5Sclose(space);
  H5Dclose(d);
  EXPECT_EQ(idx, (std::vector<uint64_t>{0, 3, 4, 4}));
  std::vector<uint32_t> t(5);
  d = H5Dopen2(file, "events/t", H5P_DEFAULT);
  hid_t type = H5Dget_type(d);
  EXPECT_TRUE(H5Tequal(type, H5T_STD_U32LE) > 0);
  H5Tclose(type);
  H5Dread(d, H5T_NATIVE_UINT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.data());
  H5Dclose(d);
  H5Fclose(file);
  EXPECT_EQ(t, (std::vector<uint32_t>{0, 0, 999, 1000, 3500}));
  EXPECT_TRUE(openEventFileReader(f.path())->readAll() == ev);
}

TEST(FormatsHdf5, DsecWriterRefusesTimesItCannotStore)
{
  TempFile f(".h5");
  Hdf5WriterOptions o;
  o.layout = Hdf5Layout::Dsec;
  Hdf5Writer w(f.path(), 640, 480, o);
  w.write({Event{1000000, 0, 0, true}});
  try
  {
    w.write({Event{999000, 0, 0, true}});
    ADD_FAILURE() << "an event before t_offset accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("t_offset"), std::string::npos) << e.what();
  }
  EXPECT_THROW(w.write({Event{(int64_t(1) << 33) * 1000, 0, 0, true}}), EventFormatError);
}

TEST(FormatsHdf5, HandBuiltDsecFile)
{
  TempFile f(".h5");
  hid_t file = H5Fcreate(f.path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hid_t g = H5Gcreate2(file, "events", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  dataset<uint16_t>(g, "x", H5T_STD_U16LE, H5T_NATIVE_UINT16, {0, 639, 700, 10});
  dataset<uint16_t>(g, "y", H5T_STD_U16LE, H5T_NATIVE_UINT16, {0, 479, 5, 20});
  dataset<uint32_t>(g, "t", H5T_STD_U32LE, H5T_NATIVE_UINT32, {0, 1, 2, 4000000000u});
  dataset<uint8_t>(g, "p", H5T_STD_U8LE, H5T_NATIVE_UINT8, {1, 0, 1, 0});
  dataset<uint64_t>(file, "ms_to_idx", H5T_STD_U64LE, H5T_NATIVE_UINT64, {0});
  scalarI64(file, "t_offset", 49599300523);
  H5Gclose(g);
  H5Fclose(file);

  auto r = openEventFileReader(f.path());
  EXPECT_EQ(r->formatName(), "HDF5 (DSEC layout)");
  EXPECT_EQ(r->width(), 640u);  // DSEC default: no size attributes
  EXPECT_EQ(r->height(), 480u);
  const EventVector ev = r->readAll();
  ASSERT_EQ(ev.size(), 3u);  // x = 700 is outside 640x480
  EXPECT_EQ(ev[0], (Event{49599300523000, 0, 0, true}));
  EXPECT_EQ(ev[1], (Event{49599300524000, 639, 479, false}));
  EXPECT_EQ(ev[2], (Event{(49599300523 + 4000000000LL) * 1000, 10, 20, false}));
  EXPECT_EQ(r->stats().out_of_range, 1u);
}

TEST(FormatsHdf5, HandBuiltFlatFileWithOtherIntegerTypesAndSizeAttributes)
{
  TempFile f(".h5");
  hid_t file = H5Fcreate(f.path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  dataset<int32_t>(file, "x", H5T_STD_I32BE, H5T_NATIVE_INT32, {3, 1279, -1});
  dataset<int32_t>(file, "y", H5T_STD_I32LE, H5T_NATIVE_INT32, {4, 719, 0});
  dataset<uint64_t>(file, "t", H5T_STD_U64LE, H5T_NATIVE_UINT64, {10, 20, 30});
  dataset<int8_t>(file, "p", H5T_STD_I8LE, H5T_NATIVE_INT8, {-1, 1, 1});
  attrU32(file, "width", 1280);
  attrU32(file, "height", 720);
  H5Fclose(file);
  auto r = openEventFileReader(f.path());
  EXPECT_EQ(r->formatName(), "HDF5 (flat x/y/t/p)");
  EXPECT_EQ(r->width(), 1280u);
  EXPECT_EQ(r->height(), 720u);
  const EventVector ev = r->readAll();
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0], (Event{10000, 3, 4, false}));  // p = -1: OFF
  EXPECT_EQ(ev[1], (Event{20000, 1279, 719, true}));
  EXPECT_EQ(r->stats().out_of_range, 1u);  // x = -1
}

TEST(FormatsHdf5, TruncatedOrCorruptFileGivesANamedError)
{
  TempFile good(".h5");
  Hdf5WriterOptions o;
  o.layout = Hdf5Layout::Dsec;
  Hdf5Writer(good.path(), 640, 480, o).write(someEvents(50000, 0, 640, 480));
  const auto bytes = formats_test::readBytes(good.path());
  TempFile cut(".h5");
  cut.write(bytes.data(), bytes.size() / 2);
  EXPECT_EQ(detectEventFormat(cut.path()), EventFormat::Hdf5);
  std::string e = errorOf(cut.path());
  EXPECT_NE(e.find("truncated or corrupt"), std::string::npos) << e;
  EXPECT_NE(e.find(cut.path()), std::string::npos) << e;

  auto garbled = bytes;
  for (size_t i = 8; i < 200 && i < garbled.size(); ++i)
    garbled[i] ^= 0x5A;
  TempFile bad(".h5");
  bad.write(garbled);
  e = errorOf(bad.path());
  EXPECT_NE(e.find("truncated or corrupt"), std::string::npos) << e;
}

TEST(FormatsHdf5, UnsupportedLayoutsAreNamed)
{
  TempFile f(".h5");
  hid_t file = H5Fcreate(f.path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hid_t g = H5Gcreate2(file, "CD", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  dataset<int64_t>(g, "events", H5T_STD_I64LE, H5T_NATIVE_INT64, {1, 2});
  H5Gclose(g);
  dataset<int64_t>(file, "images", H5T_STD_I64LE, H5T_NATIVE_INT64, {1});
  H5Fclose(file);
  std::string e = errorOf(f.path());
  EXPECT_NE(e.find("unsupported HDF5 event layout"), std::string::npos) << e;
  EXPECT_NE(e.find("CD, images"), std::string::npos) << e;
  EXPECT_NE(e.find("Prophesee"), std::string::npos) << e;

  TempFile lengths(".h5");
  file = H5Fcreate(lengths.path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  dataset<int32_t>(file, "x", H5T_STD_I32LE, H5T_NATIVE_INT32, {1, 2});
  dataset<int32_t>(file, "y", H5T_STD_I32LE, H5T_NATIVE_INT32, {1, 2});
  dataset<int32_t>(file, "t", H5T_STD_I32LE, H5T_NATIVE_INT32, {1});
  dataset<int32_t>(file, "p", H5T_STD_I32LE, H5T_NATIVE_INT32, {1, 2});
  H5Fclose(file);
  e = errorOf(lengths.path());
  EXPECT_NE(e.find("different lengths"), std::string::npos) << e;

  TempFile floats(".h5");
  file = H5Fcreate(floats.path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  dataset<int32_t>(file, "x", H5T_STD_I32LE, H5T_NATIVE_INT32, {1});
  dataset<int32_t>(file, "y", H5T_STD_I32LE, H5T_NATIVE_INT32, {1});
  dataset<double>(file, "t", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {0.5});
  dataset<int32_t>(file, "p", H5T_STD_I32LE, H5T_NATIVE_INT32, {1});
  H5Fclose(file);
  e = errorOf(floats.path());
  EXPECT_NE(e.find("/t is not an integer dataset"), std::string::npos) << e;
}

TEST(FormatsHdf5, WrittenFilesOpenInH5py)
{
  if (std::system("/usr/bin/python3 -c 'import h5py' 2>/dev/null") != 0)
    GTEST_SKIP() << "python3-h5py is not installed (scripts/debian-packages.txt lists it)";
  const EventVector ev = someEvents(10000, 777, 640, 480);
  int64_t sum_x = 0, sum_t = 0;
  for (const auto& e : ev)
  {
    sum_x += e.x;
    sum_t += e.t_ns / 1000;
  }
  for (Hdf5Layout layout : {Hdf5Layout::Flat, Hdf5Layout::Dsec})
  {
    TempFile f(".h5");
    Hdf5WriterOptions o;
    o.layout = layout;
    o.compression = Hdf5Compression::Blosc;
    Hdf5Writer(f.path(), 640, 480, o).write(ev);
    const std::string g = layout == Hdf5Layout::Dsec ? "events/" : "";
    const std::string off = layout == Hdf5Layout::Dsec ? "int(f['t_offset'][()]) * len(f['events/t'])" : "0";
    const std::string py = "import h5py,sys\nf = h5py.File('" + f.path() + "', 'r')\n" + "ok = int(f['" + g +
                           "x'][:].astype('int64').sum()) == " + std::to_string(sum_x) + " and int(f['" + g +
                           "t'][:].astype('int64').sum()) + " + off + " == " + std::to_string(sum_t) +
                           " and int(f.attrs['width']) == 640\nsys.exit(0 if ok else 1)\n";
    TempFile script(".py");
    script.write(reinterpret_cast<const uint8_t*>(py.data()), py.size());
    EXPECT_EQ(std::system(("/usr/bin/python3 " + script.path()).c_str()), 0) << py;
  }
}

TEST(FormatsHdf5, ReadsABloscDsecFileWrittenByH5py)
{
  if (std::system("/usr/bin/python3 -c 'import h5py' 2>/dev/null") != 0)
    GTEST_SKIP() << "python3-h5py is not installed (scripts/debian-packages.txt lists it)";
  TempFile f(".h5"), script(".py");
  // An independent writer: h5py with blosc (zstd, byte shuffle) in chunks of 4 events, as DSEC.
  const std::string py = "import h5py, numpy as np\n"
                         "f = h5py.File('" + f.path() + "', 'w')\n"
                         "g = f.create_group('events')\n"
                         "o = dict(compression=32001, compression_opts=(0, 0, 0, 0, 5, 1, 5), chunks=(4,))\n"
                         "g.create_dataset('x', data=np.array([1, 2, 3, 639, 5], dtype='u2'), **o)\n"
                         "g.create_dataset('y', data=np.array([10, 20, 30, 479, 50], dtype='u2'), **o)\n"
                         "g.create_dataset('t', data=np.array([0, 5, 1000, 1001, 70000], dtype='u4'), **o)\n"
                         "g.create_dataset('p', data=np.array([1, 0, 1, 0, 1], dtype='u1'), **o)\n"
                         "f.create_dataset('t_offset', data=np.int64(123456))\n"
                         "f.create_dataset('ms_to_idx', data=np.array([0, 2], dtype='u8'))\n"
                         "f.close()\n";
  script.write(reinterpret_cast<const uint8_t*>(py.data()), py.size());
  ASSERT_EQ(std::system(("/usr/bin/python3 " + script.path()).c_str()), 0) << py;
  auto r = openEventFileReader(f.path());
  EXPECT_EQ(r->formatName(), "HDF5 (DSEC layout)");
  const EventVector ev = readInBatches(*r, 2);
  const EventVector expected = {Event{123456000, 1, 10, true}, Event{123461000, 2, 20, false},
                                Event{124456000, 3, 30, true}, Event{124457000, 639, 479, false},
                                Event{193456000, 5, 50, true}};
  EXPECT_TRUE(ev == expected);
  EXPECT_EQ(r->stats().damaged_packets, 0u);
}

TEST(FormatsHdf5, MissingBloscPluginIsNamed)
{
  TempFile f(".h5");
  Hdf5WriterOptions o;
  o.compression = Hdf5Compression::Blosc;
  Hdf5Writer(f.path(), 640, 480, o).write(someEvents(100, 0, 640, 480));
  // As without hdf5-filter-plugin-blosc-serial: no plugin loading, blosc unregistered.
  unsigned state = 0;
  H5PLget_loading_state(&state);
  ASSERT_GE(H5PLset_loading_state(0), 0);
  H5Zunregister(32001);
  ASSERT_LE(H5Zfilter_avail(32001), 0);
  const std::string e = errorOf(f.path());
  EXPECT_NE(e.find("HDF5 filter 32001 (blosc), which is not available"), std::string::npos) << e;
  EXPECT_NE(e.find("hdf5-filter-plugin-blosc-serial"), std::string::npos) << e;
  TempFile g(".h5");
  EXPECT_THROW(Hdf5Writer(g.path(), 640, 480, o), EventFormatError);
  H5PLset_loading_state(state);
}
