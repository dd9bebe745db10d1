#pragma once
// One parameter mechanism for the whole suite: a table of named parameters bound to the fields
// of a parameter struct, each with its unit, bounds and documentation. The same table reads ROS
// parameters (param_table_ros.h), YAML files and command-line values, validates ranges with a
// message naming the parameter, and prints the README's parameter table, so the list of names
// exists once per package. ROS-free.
#include <functional>
#include <string>
#include <vector>

namespace dvs_driver
{
/// One parameter: a name bound to one field (exactly one of the pointers is set).
struct ParamEntry
{
  std::string name;
  double* d = nullptr;
  int* i = nullptr;
  bool* b = nullptr;
  std::string* s = nullptr;
  std::string unit;            ///< "m", "s", "deg", "px", "events", ... ("" for ratios and flags)
  double min = -1e308, max = 1e308;  ///< inclusive bounds (numbers)
  bool min_exclusive = false;  ///< min is exclusive ("must be > min")
  std::vector<std::string> choices;  ///< allowed values of a string parameter (empty: any)
  std::string doc;             ///< one sentence for the README table

  const char* typeName() const;
  /// The current value as text (YAML / README spelling).
  std::string valueText() const;
  /// "" when the value is within bounds / among the choices, else a message naming it.
  std::string check() const;
};

class ParamTable
{
public:
  /// `what` names the owner in messages ("dvs_line_tracker", "the driver").
  explicit ParamTable(std::string what = "parameters") : what_(std::move(what)) {}

  /// Add a number; bounds inclusive. Returns the entry for further settings (exclusiveMin, ...).
  ParamEntry& add(const std::string& name, double& field, const std::string& unit, double min, double max,
                  const std::string& doc);
  ParamEntry& add(const std::string& name, int& field, const std::string& unit, int min, int max,
                  const std::string& doc);
  ParamEntry& add(const std::string& name, bool& field, const std::string& doc);
  ParamEntry& add(const std::string& name, std::string& field, const std::vector<std::string>& choices,
                  const std::string& doc);
  /// Append every entry and rule of `other` (names must not repeat: std::logic_error).
  void merge(const ParamTable& other);
  /// A cross-parameter rule: returns "" when fine, else the message (naming the parameters).
  void addRule(std::function<std::string()> rule);

  const std::vector<ParamEntry>& entries() const { return entries_; }
  ParamEntry* find(const std::string& name);
  const std::string& what() const { return what_; }

  /// Every violated bound and rule, '; '-separated ("" when all parameters are valid).
  std::string validate() const;
  /// validate(), throwing std::invalid_argument("<what>: invalid parameters: ...") on a violation.
  void validateOrThrow() const;

  /// Set one parameter from text (a command line, a launch argument). Returns "" or an error
  /// naming the parameter and the value ("unknown parameter 'x'", "'abc' is not a number").
  std::string setFromText(const std::string& name, const std::string& text);

  /// Read a flat YAML mapping of names to values. Unknown names and wrong types throw
  /// std::runtime_error naming the file and the key, unless `ignore` lists the name (keys
  /// handled by the caller). Does not validate (call validateOrThrow after all sources).
  void loadYaml(const std::string& path, const std::vector<std::string>& ignore = {});

  /// The README table: | parameter | default | unit | range | meaning |, one row per entry, with
  /// the current values as defaults.
  std::string markdownTable() const;

private:
  ParamEntry& push(ParamEntry e);
  std::string what_;
  std::vector<ParamEntry> entries_;
  std::vector<std::function<std::string()>> rules_;
};
}  // namespace dvs_driver
