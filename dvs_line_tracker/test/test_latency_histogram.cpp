// LatencyHistogram: quantiles of known samples within the bins' 4.4 %, weights, the exact
// maximum, out-of-range and invalid durations, reset.
#include <dvs_line_tracker/latency_histogram.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using dvs_line_tracker::LatencyHistogram;

TEST(LatencyHistogram, QuantilesOfKnownSamplesWithinOneBin)
{
  LatencyHistogram h;
  EXPECT_EQ(h.quantile(0.5), 0.0);
  EXPECT_EQ(h.summaryMs(), "no samples");
  for (int i = 1; i <= 1000; ++i)  // 1 us ... 1 ms
    h.add(i * 1e-6);
  EXPECT_EQ(h.count(), 1000u);
  EXPECT_DOUBLE_EQ(h.max(), 1e-3);
  const double step = std::exp2(1.0 / LatencyHistogram::kBinsPerOctave);  // one bin: 4.4 %
  for (double q : {0.01, 0.1, 0.5, 0.9, 0.99})
  {
    const double exact = q * 1e-3;  // the ceil(q N)-th sample
    EXPECT_GE(h.quantile(q), exact * (1 - 1e-12)) << q;
    EXPECT_LE(h.quantile(q), exact * step * (1 + 1e-12)) << q;
  }
  EXPECT_DOUBLE_EQ(h.quantile(1.0), 1e-3);  // never beyond the maximum
  EXPECT_NE(h.summaryMs().find("(1000)"), std::string::npos) << h.summaryMs();
}

TEST(LatencyHistogram, WeightsCountLikeRepeatedSamples)
{
  LatencyHistogram a, b;
  a.add(2e-3, 98);
  a.add(50e-3, 2);
  for (int i = 0; i < 98; ++i)
    b.add(2e-3);
  b.add(50e-3);
  b.add(50e-3);
  EXPECT_EQ(a.count(), 100u);
  for (double q : {0.5, 0.98, 0.99, 1.0})
    EXPECT_DOUBLE_EQ(a.quantile(q), b.quantile(q)) << q;
  EXPECT_LT(a.quantile(0.98), 2.1e-3);  // 98 of 100 at 2 ms
  EXPECT_GT(a.quantile(0.99), 45e-3);   // the 99th is one of the two at 50 ms
}

TEST(LatencyHistogram, ExtremesInvalidAndReset)
{
  LatencyHistogram h;
  h.add(0.0);
  h.add(1e-9);
  EXPECT_LE(h.quantile(1.0), 1e-9);  // the first bin, capped by the maximum
  h.add(1e6);                        // beyond the last bin: counted there, max exact
  EXPECT_DOUBLE_EQ(h.max(), 1e6);
  EXPECT_DOUBLE_EQ(h.quantile(1.0), 1e6);
  h.add(-1e-3);
  h.add(std::numeric_limits<double>::quiet_NaN(), 5);
  EXPECT_EQ(h.count(), 3u);
  EXPECT_EQ(h.invalid(), 6u);
  h.reset();
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.invalid(), 0u);
  EXPECT_EQ(h.max(), 0.0);
}

// LatencySplit: the parts of known packets add up to the total per event; a clock far from the
// events' times (a replay without use_sim_time) is counted, not mixed into the total.
#include <dvs_line_tracker/latency_split.h>

TEST(LatencySplit, PartsOfKnownPacketsAddUpPerEvent)
{
  dvs_line_tracker::LatencySplit s;
  dvs_line_tracker::PacketTiming p;
  p.last_event_ns = 1000000000;             // events at 0.999, 0.9995, 1.0 s
  p.arrival_clock_ns = 1000000000 + 200000;  // transport 0.2 ms
  p.queue_s = 0.1e-3;
  p.processing_s = 0.3e-3;
  p.publishing_s = 0.05e-3;
  p.events = 3;
  s.beginPacket(p);
  for (int64_t t : {999000000, 999500000, 1000000000})
    s.addEvent(t);
  EXPECT_EQ(s.total().count(), 3u);
  EXPECT_EQ(s.transport().count(), 3u);
  EXPECT_EQ(s.queue().count(), 3u);
  const double tol = std::exp2(1.0 / dvs_line_tracker::LatencyHistogram::kBinsPerOctave) * (1 + 1e-12);
  // totals 1.65, 1.15, 0.65 ms: the maximum exact, the median within one bin
  EXPECT_NEAR(s.total().max(), 1.65e-3, 1e-12);
  EXPECT_GE(s.total().quantile(0.5), 1.15e-3 * (1 - 1e-12));
  EXPECT_LE(s.total().quantile(0.5), 1.15e-3 * tol);
  EXPECT_NEAR(s.accumulation().max(), 1e-3, 1e-12);
  EXPECT_NEAR(s.transport().max(), 0.2e-3, 1e-12);
  EXPECT_NEAR(s.processing().max(), 0.3e-3, 1e-12);
  EXPECT_EQ(s.clockMismatches(), 0u);

  p.arrival_clock_ns = p.last_event_ns + int64_t(3600e9);  // the clock an hour away
  s.beginPacket(p);
  s.addEvent(p.last_event_ns);
  EXPECT_EQ(s.clockMismatches(), 1u);
  EXPECT_EQ(s.total().count(), 3u);      // not counted
  EXPECT_EQ(s.transport().count(), 3u);  // not counted
  EXPECT_EQ(s.queue().count(), 6u);      // wall-time parts still are
  EXPECT_EQ(s.accumulation().count(), 4u);
  s.reset();
  EXPECT_EQ(s.total().count(), 0u);
  EXPECT_EQ(s.clockMismatches(), 0u);
}
