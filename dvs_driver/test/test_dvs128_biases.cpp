#include <dvs_driver/dvs128_biases.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <unistd.h>

using dvs_driver::BiasError;
using dvs_driver::Dvs128Biases;

namespace
{
const std::string kDir = BIAS_DIR;

std::string writeTemp(const std::string& text)
{
  const std::string p = "/tmp/dvs_bias_test_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(Dvs128Biases, PresetFilesHoldTheDocumentedValues)
{
  const Dvs128Biases fast = dvs_driver::loadBiasesYaml(dvs_driver::biasPresetPath(kDir, "fast"));
  EXPECT_EQ(dvs_driver::fastBiases(), fast);
  EXPECT_EQ(1992u, fast.get("cas"));
  EXPECT_EQ(217u, fast.get("Pr"));
  const Dvs128Biases standard = dvs_driver::loadBiasesYaml(dvs_driver::biasPresetPath(kDir, "standard"));
  const Dvs128Biases slow = dvs_driver::loadBiasesYaml(dvs_driver::biasPresetPath(kDir, "slow"));
  EXPECT_EQ(54u, standard.get("cas"));
  EXPECT_EQ(262144u, standard.get("diffOn"));
  // slow = standard except diffOn = 482443.
  Dvs128Biases expect_slow = standard;
  expect_slow.set("diffOn", 482443);
  EXPECT_EQ(expect_slow, slow);
}

TEST(Dvs128Biases, EncodesTwelve24BitBigEndianValues)
{
  Dvs128Biases b;
  for (size_t i = 0; i < 12; ++i)
    b.values[i] = static_cast<uint32_t>(0x010203 * (i + 1));
  b.values[11] = 16777215;
  const auto bytes = dvs_driver::encodeBiases(b);
  ASSERT_EQ(36u, bytes.size());
  EXPECT_EQ(0x01, bytes[0]);
  EXPECT_EQ(0x02, bytes[1]);
  EXPECT_EQ(0x03, bytes[2]);
  EXPECT_EQ(0x02, bytes[3]);  // 0x020406
  EXPECT_EQ(0x04, bytes[4]);
  EXPECT_EQ(0x06, bytes[5]);
  EXPECT_EQ(0xFF, bytes[33]);
  EXPECT_EQ(0xFF, bytes[35]);
}

TEST(Dvs128Biases, ClearErrors)
{
  Dvs128Biases b;
  EXPECT_THROW(b.set("nope", 1), BiasError);
  EXPECT_THROW(b.set("cas", 16777216), BiasError);
  EXPECT_THROW(dvs_driver::biasPresetPath(kDir, "turbo"), BiasError);
  EXPECT_THROW(dvs_driver::loadBiasesYaml("/nonexistent.yaml"), BiasError);
  const std::string missing = writeTemp("cas: 1\n");
  try
  {
    dvs_driver::loadBiasesYaml(missing);
    FAIL();
  }
  catch (const BiasError& e)
  {
    EXPECT_NE(std::string::npos, std::string(e.what()).find("bias injGnd missing")) << e.what();
  }
  const std::string neg = writeTemp("cas: -1\n");
  EXPECT_THROW(dvs_driver::loadBiasesYaml(neg), BiasError);
  const std::string text = writeTemp("cas: abc\n");
  EXPECT_THROW(dvs_driver::loadBiasesYaml(text), BiasError);
  std::remove(missing.c_str());
}
