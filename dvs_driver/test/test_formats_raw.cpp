// Prophesee RAW EVT 3.0 / EVT 2.0 readers and the EVT 3.0 writer: the known answers of the real
// samples (../shared/data/formats/README.md), hand-built word streams, damaged files and round
// trips.
#include "formats_test_util.h"

#include <dvs_driver/formats/evt3_decoder.h>
#include <dvs_driver/formats/prophesee_raw.h>

#include <random>

using namespace dvs_driver;
using namespace formats_test;

namespace
{
const std::string kEvt3 = "prophesee_evt3_gen41_1280x720.raw";
const std::string kEvt2 = "prophesee_evt2_gen3_640x480.raw";

std::vector<uint8_t> rawFile(const std::string& header, const std::vector<uint16_t>& words)
{
  std::vector<uint8_t> b(header.begin(), header.end());
  for (uint16_t w : words)
  {
    b.push_back(uint8_t(w & 0xFF));
    b.push_back(uint8_t(w >> 8));
  }
  return b;
}
}  // namespace

TEST(FormatsRaw, DetectsFromTheFirstBytesNotTheName)
{
  EXPECT_EQ(detectEventFormat(sample(kEvt3)), EventFormat::PropheseeRaw);
  EXPECT_EQ(detectEventFormat(sample(kEvt2)), EventFormat::PropheseeRaw);
  EXPECT_EQ(detectEventFormat(sample("dvxplorer_320x240.aedat4")), EventFormat::Aedat4);
  TempFile misnamed(".aedat4");
  misnamed.write(readBytes(sample(kEvt3)));
  auto r = openEventFileReader(misnamed.path());
  EXPECT_EQ(r->formatName(), "Prophesee RAW EVT 3.0");
  EXPECT_EQ(detectEventFormat(reinterpret_cast<const uint8_t*>("#ROSBAG V2.0\n"), 13), EventFormat::RosBag1);
  EXPECT_EQ(detectEventFormat(reinterpret_cast<const uint8_t*>("\x89HDF\r\n\x1a\n"), 8), EventFormat::Hdf5);
  EXPECT_EQ(detectEventFormat(reinterpret_cast<const uint8_t*>("#!AER-DAT3.1\r\n"), 14), EventFormat::Aedat3);
  EXPECT_EQ(detectEventFormat(reinterpret_cast<const uint8_t*>("0.001 1 2 1\n"), 12), EventFormat::Unknown);
  TempFile hdf(".h5");
  hdf.write(reinterpret_cast<const uint8_t*>("\x89HDF\r\n\x1a\n\0\0\0\0"), 12);
  try
  {
    openEventFileReader(hdf.path());
    ADD_FAILURE() << "a 12-byte HDF5 stub accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("not a readable HDF5 file"), std::string::npos) << e.what();
  }
  TempFile junk(".raw");
  junk.write(std::vector<uint8_t>{1, 2, 3, 4, 5});
  EXPECT_THROW(openEventFileReader(junk.path()), EventFormatError);
  EXPECT_THROW(openEventFileReader("/nonexistent/file.raw"), EventFormatError);
}

TEST(FormatsRaw, Evt3SampleKnownAnswers)
{
  auto r = openEventFileReader(sample(kEvt3));
  EXPECT_EQ(r->formatName(), "Prophesee RAW EVT 3.0");
  EXPECT_EQ(r->width(), 1280u);  // from system_ID 48
  EXPECT_EQ(r->height(), 720u);
  const EventVector events = r->readAll();
  const Summary s = summarize(events);
  EXPECT_EQ(s.n, 219596u);
  EXPECT_EQ(s.on, 115532u);
  EXPECT_EQ(s.n - s.on, 104064u);
  EXPECT_EQ(s.min_x, 0);
  EXPECT_EQ(s.max_x, 1279);
  EXPECT_EQ(s.min_y, 0);
  EXPECT_EQ(s.max_y, 719);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front(), ev(874, 200, 11718656, 0));
  EXPECT_EQ(events.back(), ev(1218, 572, 11727457, 1));
  EXPECT_EQ(events.back().t_ns - events.front().t_ns, 8801000);
  const ReaderStats st = r->stats();
  EXPECT_EQ(st.events, 219596u);
  EXPECT_EQ(st.time_backsteps, 9u);  // the 9 TIME_LOW back steps, taken as they are
  EXPECT_EQ(st.time_wraps, 0u);
  EXPECT_EQ(st.unknown_words, 0u);
  EXPECT_EQ(st.out_of_range, 0u);
  EXPECT_FALSE(st.truncated);
  EXPECT_EQ(st.bytes_read, 618052u);
}

TEST(FormatsRaw, Evt2SampleKnownAnswers)
{
  auto r = openEventFileReader(sample(kEvt2));
  EXPECT_EQ(r->formatName(), "Prophesee RAW EVT 2.0");
  EXPECT_EQ(r->width(), 640u);  // from system_ID 21
  EXPECT_EQ(r->height(), 480u);
  const EventVector events = r->readAll();
  const Summary s = summarize(events);
  EXPECT_EQ(s.n, 539481u);
  EXPECT_EQ(s.on, 367855u);
  EXPECT_EQ(s.n - s.on, 171626u);
  EXPECT_EQ(s.min_x, 60);
  EXPECT_EQ(s.max_x, 599);
  EXPECT_EQ(s.min_y, 18);
  EXPECT_EQ(s.max_y, 475);
  EXPECT_EQ(events.front(), ev(237, 121, 1317888, 1));
  EXPECT_EQ(events.back(), ev(210, 142, 1367888, 1));
  EXPECT_EQ(events.back().t_ns - events.front().t_ns, 50000000);
  EXPECT_EQ(r->stats().unknown_words, 0u);
  EXPECT_FALSE(r->stats().truncated);
}

TEST(FormatsRaw, BatchSizeDoesNotChangeTheEvents)
{
  const EventVector all = openEventFileReader(sample(kEvt3))->readAll();
  for (size_t batch : {size_t(1), size_t(7), size_t(1000), size_t(65536)})
  {
    auto r = openEventFileReader(sample(kEvt3));
    EXPECT_EQ(readInBatches(*r, batch), all) << "batch " << batch;
  }
}

TEST(FormatsRaw, DecoderStateCarriesAcrossArbitraryPieces)
{
  // Feeding the words in pieces of any size (e.g. message payloads) gives the same events.
  const std::vector<uint8_t> bytes = readBytes(sample(kEvt3));
  const size_t start = 166, n_words = (bytes.size() - start) / 2;
  const EventVector all = openEventFileReader(sample(kEvt3))->readAll();
  formats::Evt3Decoder dec(1280, 720);
  ReaderStats st;
  EventVector out(all.size() + 64);
  Event* p = out.data();
  std::mt19937 rng(3);
  size_t w = 0;
  while (w < n_words)
  {
    size_t piece = std::min<size_t>(1 + rng() % 5000, n_words - w), used = 0;
    p = dec.decode(bytes.data() + start + 2 * w, piece, p, out.data() + out.size(), used, st, nullptr);
    ASSERT_EQ(used, piece);
    w += piece;
  }
  out.resize(size_t(p - out.data()));
  EXPECT_EQ(out, all);
}

TEST(FormatsRaw, HeaderSizeSources)
{
  std::string h = "% format EVT3;height=480;width=640\n% geometry 1280x720\n% end\n";
  formats::RawHeader r = formats::parseRawHeader(reinterpret_cast<const uint8_t*>(h.data()), h.size(), "x");
  EXPECT_EQ(r.evt, 3);
  EXPECT_EQ(r.width, 640u);
  EXPECT_EQ(r.height, 480u);
  EXPECT_EQ(r.size_source, "format");
  EXPECT_EQ(r.data_offset, h.size());
  h = "% evt 2.0\n% geometry 1280x720\n";
  r = formats::parseRawHeader(reinterpret_cast<const uint8_t*>(h.data()), h.size(), "x");
  EXPECT_EQ(r.evt, 2);
  EXPECT_EQ(r.width, 1280u);
  EXPECT_EQ(r.size_source, "geometry");
  h = "% evt 3.0\n% system_ID 12345\n";
  r = formats::parseRawHeader(reinterpret_cast<const uint8_t*>(h.data()), h.size(), "x");
  EXPECT_EQ(r.width, 0u);
  EXPECT_EQ(r.size_source, "");
}

TEST(FormatsRaw, UnsupportedVersionIsNamed)
{
  TempFile f(".raw");
  f.write(rawFile("% format EVT21;height=720;width=1280\n% end\n", {0x8000}));
  try
  {
    openEventFileReader(f.path());
    FAIL() << "EVT 2.1 accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("'EVT21' is not supported"), std::string::npos) << e.what();
  }
  f.write(rawFile("% evt 4.0\n", {0x8000}));
  EXPECT_THROW(openEventFileReader(f.path()), EventFormatError);
  f.write(rawFile("% format EVT3\n% endianness big\n", {0x8000}));
  try
  {
    openEventFileReader(f.path());
    FAIL() << "big endian accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("endianness 'big'"), std::string::npos) << e.what();
  }
}

TEST(FormatsRaw, Evt3HandBuiltWordsVectorsTriggersWrapsAndUnknownWords)
{
  TempFile f(".raw");
  f.write(rawFile("% format EVT3;height=100;width=40\n% end\n",
                  {
                      0x2005,           // ADDR_X before any time: dropped
                      0x8FFF, 0x6FFE,   // TIME_HIGH 4095, TIME_LOW 4094: t = 16777214 us
                      0x0007,           // ADDR_Y 7
                      0x2803,           // ON at x 3
                      0x9123,           // unknown type 0x9: skipped, counted
                      0x3800 | 10,      // VECT_BASE_X 10, ON
                      0x4000 | 0x805,   // VECT_12: bits 0, 2, 11 -> x 10, 12, 21; base 22
                      0x5000 | 0x81,    // VECT_8: bits 0, 7 -> x 22, 29; base 30
                      0x5000 | 0xFF,    // VECT_8 at base 30: x 30..37; base 38
                      0x4000 | 0x7,     // VECT_12 at base 38: x 38, 39 kept, 40 (width 40) dropped
                      0xA000 | 0x301,   // EXT_TRIGGER channel 3, rising
                      0x8001,           // TIME_HIGH 1 after 4095: a wrap; TIME_LOW zeroed
                      0x2002,           // OFF at x 2, t = 2^24 + 4096 us
                      0x2000 | 45,      // x 45 >= width 40: dropped
                      0xE000, 0xF000,   // OTHERS + CONTINUED_12: skipped
                      0x6005, 0x0063,   // TIME_LOW 5, ADDR_Y 99
                      0x2801,           // ON at (1, 99)
                  }));
  auto r = openEventFileReader(f.path());
  EXPECT_EQ(r->width(), 40u);
  EXPECT_EQ(r->height(), 100u);
  const EventVector e = r->readAll();
  const int64_t t0 = 16777214, t1 = (int64_t(1) << 24) + 4096;
  EventVector want = {ev(3, 7, t0, 1), ev(10, 7, t0, 1), ev(12, 7, t0, 1), ev(21, 7, t0, 1),
                      ev(22, 7, t0, 1), ev(29, 7, t0, 1)};
  for (int x = 30; x < 40; ++x)
    want.push_back(ev(x, 7, t0, 1));
  want.push_back(ev(2, 7, t1, 0));
  want.push_back(ev(1, 99, t1 + 5, 1));
  EXPECT_EQ(e, want);
  const ReaderStats s = r->stats();
  EXPECT_EQ(s.unknown_words, 1u);
  EXPECT_EQ(s.other_words, 2u);
  EXPECT_EQ(s.time_wraps, 1u);
  EXPECT_EQ(s.before_time, 1u);
  EXPECT_EQ(s.out_of_range, 2u);
  EXPECT_EQ(s.triggers, 1u);
  std::vector<TriggerEvent> trig;
  EXPECT_EQ(r->takeTriggers(trig), 1u);
  ASSERT_EQ(trig.size(), 1u);
  EXPECT_EQ(trig[0], (TriggerEvent{t0 * 1000, 3, true}));
}

TEST(FormatsRaw, Evt2HandBuiltWordsWrapTriggerUnknown)
{
  auto w32 = [](std::vector<uint8_t>& b, uint32_t w) {
    for (int i = 0; i < 4; ++i)
      b.push_back(uint8_t(w >> (8 * i)));
  };
  std::string h = "% evt 2.0\n% geometry 64x48\n";
  std::vector<uint8_t> b(h.begin(), h.end());
  w32(b, 0x10000000 | (3 << 11) | 4);           // CD before TIME_HIGH: dropped
  w32(b, 0x80000000 | 0x0FFFFFFF);              // TIME_HIGH max: t = (2^28 - 1) * 64
  w32(b, 0x10000000 | (5u << 22) | (3 << 11) | 4);  // ON (3, 4) at + 5
  w32(b, 0xA0000000 | (7u << 22) | (2 << 8) | 1);   // trigger channel 2 rising at + 7
  w32(b, 0x50000000);                           // reserved type 5: skipped
  w32(b, 0x80000000 | 1);                       // TIME_HIGH 1: wrap (2^34)
  w32(b, 0x00000000 | (63u << 22) | (63 << 11) | 47);  // OFF (63, 47) at 2^34 + 64 + 63
  w32(b, 0x00000000 | (64 << 11) | 1);         // x 64 out of range
  b.push_back(0xAB);                            // 3 stray bytes: truncated word
  b.push_back(0xCD);
  b.push_back(0xEF);
  TempFile f(".raw");
  f.write(b);
  auto r = openEventFileReader(f.path());
  const EventVector e = r->readAll();
  const int64_t th = (int64_t(1) << 28) - 1;
  EXPECT_EQ(e, (EventVector{ev(3, 4, th * 64 + 5, 1), ev(63, 47, (int64_t(1) << 34) + 64 + 63, 0)}));
  const ReaderStats s = r->stats();
  EXPECT_EQ(s.before_time, 1u);
  EXPECT_EQ(s.unknown_words, 1u);
  EXPECT_EQ(s.out_of_range, 1u);
  EXPECT_EQ(s.time_wraps, 1u);
  EXPECT_TRUE(s.truncated);
  EXPECT_EQ(s.truncated_offset, h.size() + 8 * 4);
  EXPECT_EQ(s.truncated_bytes, 3u);
  std::vector<TriggerEvent> trig;
  r->takeTriggers(trig);
  EXPECT_EQ(trig, (std::vector<TriggerEvent>{TriggerEvent{(th * 64 + 7) * 1000, 2, true}}));
}

TEST(FormatsRaw, TruncatedEvt3SampleDeliversEverythingBeforeTheDamage)
{
  // Cut the GPL sample inside a word (odd length) into a temporary file.
  const std::vector<uint8_t> bytes = readBytes(sample(kEvt3));
  const size_t cut = 166 + 2 * 150000 + 1;
  TempFile f(".raw");
  f.write(bytes.data(), cut);
  auto r = openEventFileReader(f.path());
  const EventVector part = r->readAll();
  // Reference: the decoder over the first 150000 complete words.
  formats::Evt3Decoder dec(1280, 720);
  ReaderStats st;
  EventVector want(200000);
  size_t used = 0;
  Event* p = dec.decode(bytes.data() + 166, 150000, want.data(), want.data() + want.size() - 16, used, st, nullptr);
  want.resize(size_t(p - want.data()));
  EXPECT_GT(want.size(), 100000u);
  EXPECT_EQ(part, want);
  const ReaderStats s = r->stats();
  EXPECT_TRUE(s.truncated);
  EXPECT_EQ(s.truncated_offset, cut - 1);
  EXPECT_EQ(s.truncated_bytes, 1u);
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings.back().find("byte " + std::to_string(cut - 1)), std::string::npos) << s.warnings.back();
}

TEST(FormatsRaw, Evt3WriterRoundTripOfTheSample)
{
  // The sample holds TIME_LOW back steps: they must survive the round trip.
  const EventVector all = openEventFileReader(sample(kEvt3))->readAll();
  TempFile f(".raw");
  {
    formats::Evt3Writer w(f.path(), 1280, 720);
    w.write(all);
    w.close();
  }
  auto r = openEventFileReader(f.path());
  EXPECT_EQ(r->formatName(), "Prophesee RAW EVT 3.0");
  EXPECT_EQ(r->width(), 1280u);
  EXPECT_EQ(r->height(), 720u);
  EXPECT_EQ(r->readAll(), all);
  EXPECT_EQ(r->stats().unknown_words, 0u);
}

TEST(FormatsRaw, Evt3WriterRoundTripAcrossWrapsAndEpochTimes)
{
  std::mt19937_64 rng(7);
  for (int64_t origin_us : {int64_t(0), int64_t(1605537493718345)})
  {
    EventVector ev;
    int64_t t = origin_us;
    for (int i = 0; i < 20000; ++i)
    {
      // mostly small steps, sometimes seconds, sometimes several 2^24 us loops
      const uint64_t k = rng() % 1000;
      t += k < 990 ? int64_t(rng() % 50) : k < 998 ? int64_t(rng() % 5000000) : int64_t(rng() % 200000000);
      ev.push_back(Event{t * 1000, uint16_t(rng() % 2048), uint16_t(rng() % 2048), bool(rng() & 1)});
    }
    TempFile f(".raw");
    formats::Evt3Writer w(f.path(), 2048, 2048);
    w.write(ev);
    w.close();
    auto r = openEventFileReader(f.path());
    EXPECT_EQ(r->readAll(), ev) << "origin " << origin_us;
    EXPECT_GT(r->stats().time_wraps, 0u);
  }
}

TEST(FormatsRaw, Evt3WriterRejectsWhatItCannotStore)
{
  TempFile f(".raw");
  EXPECT_THROW(formats::Evt3Writer(f.path(), 4096, 10), EventFormatError);
  formats::Evt3Writer w(f.path(), 10, 10);
  EXPECT_THROW(w.write(EventVector{Event{0, 10, 0, true}}), EventFormatError);  // x outside
  w.write(EventVector{Event{20000000000, 1, 1, true}});                          // 20 s
  EXPECT_THROW(w.write(EventVector{Event{1000000000, 1, 1, true}}), EventFormatError);  // 19 s back
}
