#include <dvs_driver/event_text_io.h>
#include <gtest/gtest.h>

#include <sstream>

using dvs_driver::Event;
using dvs_driver::EventFileError;

TEST(EventTextIo, ParsesSecondsExactlyToNanoseconds)
{
  int64_t ns = 0;
  const std::string s = "1468940843.123456789";
  ASSERT_TRUE(dvs_driver::parseSecondsToNs(s.data(), s.data() + s.size(), ns));
  EXPECT_EQ(1468940843123456789LL, ns);
  const std::string t = "0.5";
  ASSERT_TRUE(dvs_driver::parseSecondsToNs(t.data(), t.data() + t.size(), ns));
  EXPECT_EQ(500000000LL, ns);
  const std::string u = "-2.000000001";
  ASSERT_TRUE(dvs_driver::parseSecondsToNs(u.data(), u.data() + u.size(), ns));
  EXPECT_EQ(-2000000001LL, ns);
  const std::string bad = "1.2.3";
  EXPECT_FALSE(dvs_driver::parseSecondsToNs(bad.data(), bad.data() + bad.size(), ns));
  // Found by fuzzing: 80020000100 s overflowed int64 nanoseconds; the largest accepted is 9e9 s.
  const std::string huge = "80020000100";
  EXPECT_FALSE(dvs_driver::parseSecondsToNs(huge.data(), huge.data() + huge.size(), ns));
  const std::string largest = "9000000000.999999999";
  ASSERT_TRUE(dvs_driver::parseSecondsToNs(largest.data(), largest.data() + largest.size(), ns));
  EXPECT_EQ(9000000000999999999LL, ns);
}

TEST(EventTextIo, RoundTripKeepsEveryField)
{
  dvs_driver::EventVector in;
  for (int i = 0; i < 1000; ++i)
  {
    Event e;
    e.t_ns = 1000000000LL * 3 + 12345LL * i + 7;
    e.x = static_cast<uint16_t>(i % 346);
    e.y = static_cast<uint16_t>((i * 7) % 260);
    e.polarity = (i % 3) == 0;
    in.push_back(e);
  }
  std::stringstream ss;
  dvs_driver::writeEventsText(ss, in);
  const dvs_driver::EventVector out = dvs_driver::readEventsText(ss, "memory");
  ASSERT_EQ(in.size(), out.size());
  for (size_t i = 0; i < in.size(); ++i)
    ASSERT_EQ(in[i], out[i]) << "event " << i;
}

TEST(EventTextIo, SkipsCommentsAndBlankLines)
{
  std::stringstream ss("# t x y p\n\n0.001 1 2 1\n  0.002\t3 4 0\r\n");
  const auto ev = dvs_driver::readEventsText(ss, "memory");
  ASSERT_EQ(2u, ev.size());
  EXPECT_EQ(1000000, ev[0].t_ns);
  EXPECT_EQ(3, ev[1].x);
  EXPECT_EQ(4, ev[1].y);
  EXPECT_FALSE(ev[1].polarity);
}

TEST(EventTextIo, MalformedLinesNameFileAndLine)
{
  const char* bad[] = {"0.1 1 2\n", "0.1 1 2 3\n", "abc 1 2 1\n", "0.1 -1 2 1\n", "0.2 1 1 1\n0.1 1 1 1\n",
                       "0.1 1 2 1 9\n", "0.1 1.5 2 1\n"};
  for (const char* text : bad)
  {
    std::stringstream ss(text);
    try
    {
      dvs_driver::readEventsText(ss, "bad.txt");
      ADD_FAILURE() << "accepted malformed input: " << text;
    }
    catch (const EventFileError& e)
    {
      EXPECT_NE(std::string::npos, std::string(e.what()).find("bad.txt:")) << e.what();
    }
  }
}

TEST(EventTextIo, MissingFileGivesClearError)
{
  EXPECT_THROW(dvs_driver::readEventsText("/nonexistent/events.txt"), EventFileError);
}
