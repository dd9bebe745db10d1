#include <dvs_driver/param_table.h>

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dvs_driver
{
namespace
{
std::string numberText(double v)
{
  if (v >= 1e300)
    return "inf";
  if (v <= -1e300)
    return "-inf";
  std::ostringstream s;
  s << v;
  return s.str();
}

bool parseDouble(const std::string& text, double& v)
{
  if (text.empty())
    return false;
  char* end = nullptr;
  errno = 0;
  v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && errno == 0;
}

bool parseInt(const std::string& text, int& v)
{
  if (text.empty())
    return false;
  char* end = nullptr;
  errno = 0;
  const long long x = std::strtoll(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || errno != 0 || x < std::numeric_limits<int>::min() ||
      x > std::numeric_limits<int>::max())
    return false;
  v = static_cast<int>(x);
  return true;
}

bool parseBool(const std::string& text, bool& v)
{
  if (text == "true" || text == "True" || text == "1" || text == "yes")
    v = true;
  else if (text == "false" || text == "False" || text == "0" || text == "no")
    v = false;
  else
    return false;
  return true;
}
}  // namespace

const char* ParamEntry::typeName() const
{
  return d ? "double" : i ? "int" : b ? "bool" : "string";
}

std::string ParamEntry::valueText() const
{
  if (d)
    return numberText(*d);
  if (i)
    return std::to_string(*i);
  if (b)
    return *b ? "true" : "false";
  return s ? *s : std::string();
}

std::string ParamEntry::check() const
{
  std::ostringstream err;
  if (d || i)
  {
    const double v = d ? *d : static_cast<double>(*i);
    const bool below = min_exclusive ? !(v > min) : !(v >= min);
    if (!std::isfinite(v) || below || !(v <= max))
    {
      err << name << " must be ";
      if (max >= 1e300)
        err << (min_exclusive ? "> " : ">= ") << numberText(min);
      else
        err << "in " << (min_exclusive ? "(" : "[") << numberText(min) << ", " << numberText(max) << "]";
      if (!unit.empty())
        err << " " << unit;
      err << " (got " << valueText() << ")";
    }
  }
  else if (s && !choices.empty())
  {
    bool ok = false;
    for (const auto& c : choices)
      ok |= c == *s;
    if (!ok)
    {
      err << name << " must be one of";
      for (const auto& c : choices)
        err << " '" << c << "'";
      err << " (got '" << *s << "')";
    }
  }
  return err.str();
}

ParamEntry& ParamTable::push(ParamEntry e)
{
  for (const auto& existing : entries_)
    if (existing.name == e.name)
      throw std::logic_error(what_ + ": parameter '" + e.name + "' declared twice");
  entries_.push_back(std::move(e));
  return entries_.back();
}

namespace
{
ParamEntry numberEntry(const std::string& name, const std::string& unit, double min, double max, const std::string& doc)
{
  ParamEntry e;
  e.name = name;
  e.unit = unit;
  e.min = min;
  e.max = max;
  e.doc = doc;
  return e;
}
}  // namespace

ParamEntry& ParamTable::add(const std::string& name, double& field, const std::string& unit, double min,
                            double max, const std::string& doc)
{
  ParamEntry e = numberEntry(name, unit, min, max, doc);
  e.d = &field;
  return push(std::move(e));
}

ParamEntry& ParamTable::add(const std::string& name, int& field, const std::string& unit, int min, int max,
                            const std::string& doc)
{
  ParamEntry e = numberEntry(name, unit, min, max, doc);
  e.i = &field;
  return push(std::move(e));
}

ParamEntry& ParamTable::add(const std::string& name, bool& field, const std::string& doc)
{
  ParamEntry e;
  e.name = name;
  e.b = &field;
  e.doc = doc;
  return push(std::move(e));
}

ParamEntry& ParamTable::add(const std::string& name, std::string& field, const std::vector<std::string>& choices,
                            const std::string& doc)
{
  ParamEntry e;
  e.name = name;
  e.s = &field;
  e.choices = choices;
  e.doc = doc;
  return push(std::move(e));
}

void ParamTable::merge(const ParamTable& other)
{
  for (const auto& e : other.entries_)
    push(e);
  for (const auto& r : other.rules_)
    rules_.push_back(r);
}

void ParamTable::addRule(std::function<std::string()> rule) { rules_.push_back(std::move(rule)); }

ParamEntry* ParamTable::find(const std::string& name)
{
  for (auto& e : entries_)
    if (e.name == name)
      return &e;
  return nullptr;
}

std::string ParamTable::validate() const
{
  std::string all;
  auto append = [&](const std::string& m) {
    if (m.empty())
      return;
    if (!all.empty())
      all += "; ";
    all += m;
  };
  for (const auto& e : entries_)
    append(e.check());
  for (const auto& rule : rules_)
    append(rule());
  return all;
}

void ParamTable::validateOrThrow() const
{
  const std::string err = validate();
  if (!err.empty())
    throw std::invalid_argument(what_ + ": invalid parameters: " + err);
}

std::string ParamTable::setFromText(const std::string& name, const std::string& text)
{
  ParamEntry* e = find(name);
  if (!e)
    return what_ + ": unknown parameter '" + name + "'";
  bool ok = true;
  if (e->d)
    ok = parseDouble(text, *e->d);
  else if (e->i)
    ok = parseInt(text, *e->i);
  else if (e->b)
    ok = parseBool(text, *e->b);
  else
    *e->s = text;
  if (!ok)
    return what_ + ": parameter '" + name + "': '" + text + "' is not " +
           (e->d ? "a number" : e->i ? "an integer" : "true or false");
  return "";
}

void ParamTable::loadYaml(const std::string& path, const std::vector<std::string>& ignore)
{
  YAML::Node root;
  try
  {
    root = YAML::LoadFile(path);
  }
  catch (const YAML::Exception& ex)
  {
    throw std::runtime_error("cannot read parameter file '" + path + "': " + ex.what());
  }
  if (root.IsNull())
    return;
  if (!root.IsMap())
    throw std::runtime_error(path + ": expected a mapping of parameter names to values");
  for (const auto& kv : root)
  {
    std::string key;
    try
    {
      key = kv.first.as<std::string>();
    }
    catch (const YAML::Exception&)
    {
      throw std::runtime_error(path + ": a key is not a parameter name");
    }
    bool skip = false;
    for (const auto& n : ignore)
      skip |= n == key;
    if (skip)
      continue;
    ParamEntry* e = find(key);
    if (!e)
      throw std::runtime_error(path + ": unknown parameter '" + key + "'");
    if (!kv.second.IsScalar())
      throw std::runtime_error(path + ": parameter '" + key + "' must be a single value (" + e->typeName() + ")");
    try
    {
      if (e->d)
        *e->d = kv.second.as<double>();
      else if (e->i)
        *e->i = kv.second.as<int>();
      else if (e->b)
        *e->b = kv.second.as<bool>();
      else
        *e->s = kv.second.as<std::string>();
    }
    catch (const YAML::Exception&)
    {
      throw std::runtime_error(path + ": parameter '" + key + "' has the wrong type (expected " + e->typeName() +
                               ", got '" + kv.second.Scalar() + "')");
    }
  }
}

std::string ParamTable::markdownTable() const
{
  std::ostringstream out;
  out << "| parameter | default | unit | range | meaning |\n|---|---|---|---|---|\n";
  for (const auto& e : entries_)
  {
    std::string range;
    if (e.d || e.i)
    {
      if (e.max >= 1e300)
        range = std::string(e.min_exclusive ? "> " : ">= ") + numberText(e.min);
      else
        range = std::string(e.min_exclusive ? "(" : "[") + numberText(e.min) + ", " + numberText(e.max) + "]";
    }
    else if (e.s && !e.choices.empty())
    {
      for (const auto& c : e.choices)
        range += (range.empty() ? "" : ", ") + c;
    }
    out << "| `" << e.name << "` | " << (e.s ? "`" + e.valueText() + "`" : e.valueText()) << " | " << e.unit
        << " | " << range << " | " << e.doc << " |\n";
  }
  return out.str();
}
}  // namespace dvs_driver
