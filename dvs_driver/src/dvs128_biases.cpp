#include <dvs_driver/dvs128_biases.h>

#include <yaml-cpp/yaml.h>

namespace dvs_driver
{
const std::array<const char*, kDvs128BiasCount> kDvs128BiasNames = {
    "cas", "injGnd", "reqPd", "puX", "diffOff", "req", "refr", "puY", "diffOn", "diff", "foll", "Pr"};

size_t Dvs128Biases::index(const std::string& name)
{
  for (size_t i = 0; i < kDvs128BiasCount; ++i)
    if (name == kDvs128BiasNames[i])
      return i;
  std::string all;
  for (const char* n : kDvs128BiasNames)
    all += std::string(all.empty() ? "" : ", ") + n;
  throw BiasError("unknown DVS128 bias `" + name + "` (biases: " + all + ")");
}

void Dvs128Biases::set(const std::string& name, uint32_t value)
{
  const size_t i = index(name);
  if (value > kDvs128BiasMax)
    throw BiasError("bias " + name + " = " + std::to_string(value) + " exceeds 16777215 (24 bits)");
  values[i] = value;
}

Dvs128Biases fastBiases()
{
  Dvs128Biases b;
  b.values = {1992, 1108364, 16777215, 8159221, 132, 309590, 969, 16777215, 209996, 13125, 271, 217};
  return b;
}

Dvs128Biases loadBiasesYaml(const std::string& path)
{
  YAML::Node root;
  try
  {
    root = YAML::LoadFile(path);
  }
  catch (const YAML::Exception& e)
  {
    throw BiasError(path + ": cannot read bias file: " + e.what());
  }
  if (!root.IsMap())
    throw BiasError(path + ": bias file must be a map `name: value` of the 12 DVS128 biases");
  Dvs128Biases b;
  std::array<bool, kDvs128BiasCount> seen{};
  for (const auto& kv : root)
  {
    const std::string name = kv.first.as<std::string>();
    size_t i;
    try
    {
      i = Dvs128Biases::index(name);
    }
    catch (const BiasError& e)
    {
      throw BiasError(path + ": " + e.what());
    }
    long long v;
    try
    {
      v = kv.second.as<long long>();
    }
    catch (const YAML::Exception&)
    {
      throw BiasError(path + ": bias " + name + " is not an integer");
    }
    if (v < 0 || v > kDvs128BiasMax)
      throw BiasError(path + ": bias " + name + " = " + std::to_string(v) + " outside [0, 16777215]");
    b.values[i] = static_cast<uint32_t>(v);
    seen[i] = true;
  }
  for (size_t i = 0; i < kDvs128BiasCount; ++i)
    if (!seen[i])
      throw BiasError(path + ": bias " + kDvs128BiasNames[i] + " missing");
  return b;
}

std::string biasPresetPath(const std::string& dir, const std::string& preset)
{
  if (preset != "fast" && preset != "standard" && preset != "slow")
    throw BiasError("unknown bias preset `" + preset + "` (presets: fast, standard, slow)");
  return dir + "/" + preset + ".yaml";
}

std::array<uint8_t, 3 * kDvs128BiasCount> encodeBiases(const Dvs128Biases& biases)
{
  std::array<uint8_t, 3 * kDvs128BiasCount> out{};
  for (size_t i = 0; i < kDvs128BiasCount; ++i)
  {
    const uint32_t v = biases.values[i];
    out[3 * i] = static_cast<uint8_t>((v >> 16) & 0xFF);
    out[3 * i + 1] = static_cast<uint8_t>((v >> 8) & 0xFF);
    out[3 * i + 2] = static_cast<uint8_t>(v & 0xFF);
  }
  return out;
}
}  // namespace dvs_driver
