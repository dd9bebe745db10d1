#pragma once
// Command-line options through a ParamTable (param_table.h, the one parameter mechanism), so a
// tool's options are parsed, range-checked and reported by name like every ROS parameter
// (ROS-free). Name the table's entries as spelt on the command line ("--width").
//
//   dvs_driver::ParamTable t("convert");
//   t.add("--width", width, "px", 0, 65536, "sensor width; 0 = from the file");
//   t.add("--zero-time", zero_time, "shift the first event to t = 0");   // bool: a flag
//   std::vector<std::string> given;
//   if (dvs_driver::parseCommandLine(t, argc, argv, &given)) { usage(); return 0; }   // --help
//   // throws UsageError: "convert: --width: 'abc' is not an integer",
//   //                    "convert: --width must be in [0, 65536] px (got 100000)"
#include <dvs_driver/param_table.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace dvs_driver
{
/// Bad usage; the message names the option (tools exit with status 2).
class UsageError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// Reads argv[1..argc) into `table`: a bool entry is a flag (no value), every other entry takes
/// the next argument. Arguments starting with "__" (rosrun / roslaunch remappings) are skipped.
/// Validates the table (bounds and rules) at the end. Returns true when `-h` or `--help` was
/// given (nothing validated). `given` receives the names of the options present. Throws
/// UsageError naming the option: unknown, missing value, not a number, out of range (with the
/// limits), a repeated option.
bool parseCommandLine(ParamTable& table, int argc, const char* const* argv, std::vector<std::string>* given = nullptr);

/// `s` as a JSON string literal for a tool's summary line: quotes and backslashes escaped,
/// control characters dropped.
std::string jsonString(const std::string& s);
}  // namespace dvs_driver
