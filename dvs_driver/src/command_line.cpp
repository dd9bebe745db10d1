#include <dvs_driver/command_line.h>

#include <algorithm>

namespace dvs_driver
{
bool parseCommandLine(ParamTable& table, int argc, const char* const* argv, std::vector<std::string>* given)
{
  const std::string tool = table.what();
  std::vector<std::string> seen;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help")
      return true;
    if (a.rfind("__", 0) == 0)
      continue;
    ParamEntry* e = table.find(a);
    if (!e)
      throw UsageError(tool + ": unknown option `" + a + "`");
    if (std::find(seen.begin(), seen.end(), a) != seen.end())
      throw UsageError(tool + ": option " + a + " given twice");
    seen.push_back(a);
    if (e->b)
    {
      *e->b = true;
      continue;
    }
    if (i + 1 >= argc)
      throw UsageError(tool + ": option " + a + " needs a value");
    const std::string err = table.setFromText(a, argv[++i]);
    if (!err.empty())
      throw UsageError(err);
  }
  const std::string err = table.validate();
  if (!err.empty())
    throw UsageError(tool + ": " + err);
  if (given)
    *given = seen;
  return false;
}

std::string jsonString(const std::string& s)
{
  std::string o = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\')
      o += '\\';
    if (static_cast<unsigned char>(c) < 0x20)
      continue;
    o += c;
  }
  return o + "\"";
}
}  // namespace dvs_driver
