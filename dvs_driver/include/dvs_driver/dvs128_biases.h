#pragma once
// The 12 DVS128 bias currents (ROS-free): names, presets from YAML, and the 36-byte payload of
// vendor request 0xB8 (each bias 24-bit, big-endian, in the order of kDvs128BiasNames).
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace dvs_driver
{
constexpr size_t kDvs128BiasCount = 12;
constexpr uint32_t kDvs128BiasMax = 16777215;  // 2^24 - 1

/// Bias names in the order the device expects them.
extern const std::array<const char*, kDvs128BiasCount> kDvs128BiasNames;

class BiasError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

struct Dvs128Biases
{
  std::array<uint32_t, kDvs128BiasCount> values{};

  /// Index of a bias name; throws BiasError listing the valid names for an unknown one.
  static size_t index(const std::string& name);
  /// Set one bias by name; throws BiasError for an unknown name or a value > 16777215.
  void set(const std::string& name, uint32_t value);
  uint32_t get(const std::string& name) const { return values[index(name)]; }
  bool operator==(const Dvs128Biases& o) const { return values == o.values; }
  bool operator!=(const Dvs128Biases& o) const { return values != o.values; }
};

/// The "fast" preset built in (libcaer's and rpg_dvs_ros's default); equals config/biases/fast.yaml.
Dvs128Biases fastBiases();

/// Load a preset YAML file: a map with exactly the 12 bias names as keys, integer values in
/// [0, 16777215]. Throws BiasError naming the file and the problem.
Dvs128Biases loadBiasesYaml(const std::string& path);

/// `<dir>/<preset>.yaml` for preset `fast`, `standard` or `slow`; throws BiasError otherwise.
std::string biasPresetPath(const std::string& dir, const std::string& preset);

/// The 36 bytes of request 0xB8.
std::array<uint8_t, 3 * kDvs128BiasCount> encodeBiases(const Dvs128Biases& biases);
}  // namespace dvs_driver
