// The one parameter mechanism: bounds, rules, text and YAML input, the README table.
#include <dvs_driver/param_table.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace
{
struct Params
{
  double period = 0.001;
  int count = 8;
  bool loop = false;
  std::string mode = "replay";
  double lo = 1, hi = 2;
};

dvs_driver::ParamTable table(Params& p)
{
  dvs_driver::ParamTable t("test_node");
  t.add("period", p.period, "s", 0, 1, "packet period").min_exclusive = true;
  t.add("count", p.count, "events", 1, 100, "a count");
  t.add("loop", p.loop, "loop the file");
  t.add("mode", p.mode, {"replay", "now"}, "time source");
  t.add("lo", p.lo, "m", 0, 1e308, "lower");
  t.add("hi", p.hi, "m", 0, 1e308, "upper");
  t.addRule([&p]() { return p.lo < p.hi ? std::string() : "lo must be < hi"; });
  return t;
}

std::string writeTemp(const std::string& text)
{
  const std::string path = testing::TempDir() + "params_" + std::to_string(rand()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}
}  // namespace

TEST(ParamTable, DefaultsAreValid)
{
  Params p;
  EXPECT_EQ(table(p).validate(), "");
}

TEST(ParamTable, BoundsNameTheParameterAndValue)
{
  Params p;
  p.period = 0;  // exclusive minimum
  p.count = 101;
  p.mode = "later";
  const std::string err = table(p).validate();
  EXPECT_NE(err.find("period must be in (0, 1] s (got 0)"), std::string::npos) << err;
  EXPECT_NE(err.find("count must be in [1, 100] events (got 101)"), std::string::npos) << err;
  EXPECT_NE(err.find("mode must be one of 'replay' 'now' (got 'later')"), std::string::npos) << err;
  EXPECT_THROW(table(p).validateOrThrow(), std::invalid_argument);
}

TEST(ParamTable, NotFiniteIsRejected)
{
  Params p;
  p.lo = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(table(p).validate().find("lo must be >= 0"), std::string::npos);
}

TEST(ParamTable, RulesRun)
{
  Params p;
  p.lo = 3;
  EXPECT_NE(table(p).validate().find("lo must be < hi"), std::string::npos);
}

TEST(ParamTable, SetFromTextParsesAndNamesErrors)
{
  Params p;
  auto t = table(p);
  EXPECT_EQ(t.setFromText("count", "12"), "");
  EXPECT_EQ(p.count, 12);
  EXPECT_EQ(t.setFromText("loop", "true"), "");
  EXPECT_TRUE(p.loop);
  EXPECT_EQ(t.setFromText("period", "0.25"), "");
  EXPECT_DOUBLE_EQ(p.period, 0.25);
  EXPECT_NE(t.setFromText("count", "abc").find("parameter 'count': 'abc' is not an integer"), std::string::npos);
  EXPECT_NE(t.setFromText("count", "99999999999").find("not an integer"), std::string::npos);
  EXPECT_NE(t.setFromText("period", "1x").find("not a number"), std::string::npos);
  EXPECT_NE(t.setFromText("nope", "1").find("unknown parameter 'nope'"), std::string::npos);
}

TEST(ParamTable, YamlReadsKnownAndRejectsUnknownOrWrongType)
{
  Params p;
  auto t = table(p);
  t.loadYaml(writeTemp("period: 0.002\ncount: 5\nloop: true\nmode: now\nextra: 1\n"), {"extra"});
  EXPECT_DOUBLE_EQ(p.period, 0.002);
  EXPECT_EQ(p.count, 5);
  EXPECT_TRUE(p.loop);
  EXPECT_EQ(p.mode, "now");
  try
  {
    t.loadYaml(writeTemp("cuont: 5\n"));
    FAIL() << "unknown key accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("unknown parameter 'cuont'"), std::string::npos) << e.what();
  }
  try
  {
    t.loadYaml(writeTemp("count: many\n"));
    FAIL() << "wrong type accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("'count' has the wrong type"), std::string::npos) << e.what();
  }
  EXPECT_THROW(t.loadYaml(writeTemp("count: [1, 2]\n")), std::runtime_error);
  EXPECT_THROW(t.loadYaml("/nonexistent/params.yaml"), std::runtime_error);
}

TEST(ParamTable, DuplicateNamesAreAProgrammingError)
{
  double a = 0, b = 0;
  dvs_driver::ParamTable t;
  t.add("x", a, "", 0, 1, "");
  EXPECT_THROW(t.add("x", b, "", 0, 1, ""), std::logic_error);
}

TEST(ParamTable, MarkdownTableHasARowPerParameter)
{
  Params p;
  const std::string md = table(p).markdownTable();
  EXPECT_NE(md.find("| `period` | 0.001 | s | (0, 1] | packet period |"), std::string::npos) << md;
  EXPECT_NE(md.find("| `mode` | `replay` |  | replay, now | time source |"), std::string::npos) << md;
  EXPECT_NE(md.find("| `lo` | 1 | m | >= 0 | lower |"), std::string::npos) << md;
}
