#include <dvs_driver/param_table_ros.h>

#include <ros/console.h>
#include <ros/param.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dvs_driver
{
namespace
{
std::string typeOf(const XmlRpc::XmlRpcValue& v)
{
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return "a bool";
    case XmlRpc::XmlRpcValue::TypeInt:
      return "an int";
    case XmlRpc::XmlRpcValue::TypeDouble:
      return "a double";
    case XmlRpc::XmlRpcValue::TypeString:
      return "a string";
    default:
      return "a list or mapping";
  }
}
}  // namespace

std::vector<std::string> unknownRosParams(const ros::NodeHandle& pnh, const ParamTable& table,
                                          const std::vector<std::string>& also_known)
{
  std::vector<std::string> names, unknown;
  ros::param::getParamNames(names);
  const std::string prefix = pnh.getNamespace() + "/";
  for (const auto& full : names)
  {
    if (full.compare(0, prefix.size(), prefix) != 0)
      continue;
    const std::string rest = full.substr(prefix.size());
    const std::string name = rest.substr(0, rest.find('/'));
    const bool known = std::any_of(table.entries().begin(), table.entries().end(),
                                   [&](const ParamEntry& e) { return e.name == name; }) ||
                       std::find(also_known.begin(), also_known.end(), name) != also_known.end();
    if (!known && std::find(unknown.begin(), unknown.end(), name) == unknown.end())
      unknown.push_back(name);
  }
  return unknown;
}

std::vector<std::string> loadRosParams(const ros::NodeHandle& pnh, ParamTable& table,
                                       const std::vector<std::string>& also_known)
{
  for (const ParamEntry& e : table.entries())
  {
    XmlRpc::XmlRpcValue v;
    if (!pnh.getParam(e.name, v))
      continue;
    const auto t = v.getType();
    auto wrong = [&](const char* expected) {
      throw std::invalid_argument(table.what() + ": parameter ~" + e.name + " must be " + expected + " (got " +
                                  typeOf(v) + ")");
    };
    if (e.d)
    {
      if (t == XmlRpc::XmlRpcValue::TypeDouble)
        *e.d = static_cast<double>(v);
      else if (t == XmlRpc::XmlRpcValue::TypeInt)
        *e.d = static_cast<int>(v);
      else
        wrong("a number");
    }
    else if (e.i)
    {
      if (t == XmlRpc::XmlRpcValue::TypeInt)
        *e.i = static_cast<int>(v);
      else if (t == XmlRpc::XmlRpcValue::TypeDouble && std::floor(static_cast<double>(v)) == static_cast<double>(v) &&
               std::abs(static_cast<double>(v)) < 2e9)
        *e.i = static_cast<int>(static_cast<double>(v));
      else
        wrong("an integer");
    }
    else if (e.b)
    {
      if (t != XmlRpc::XmlRpcValue::TypeBoolean)
        wrong("true or false");
      *e.b = static_cast<bool>(v);
    }
    else
    {
      if (t != XmlRpc::XmlRpcValue::TypeString)
        wrong("a string");
      *e.s = static_cast<std::string>(v);
    }
  }
  const std::vector<std::string> unknown = unknownRosParams(pnh, table, also_known);
  for (const auto& name : unknown)
    ROS_WARN_STREAM(table.what() << ": unknown parameter " << pnh.getNamespace() << "/" << name
                                 << " ignored (misspelt? see the package README's parameter table)");
  table.validateOrThrow();
  return unknown;
}
}  // namespace dvs_driver
