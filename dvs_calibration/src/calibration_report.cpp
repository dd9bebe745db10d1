#include <dvs_calibration/calibration_report.h>

#include <cstdio>
#include <sstream>

namespace dvs_calibration
{
namespace
{
std::string quoted(const std::string& s)
{
  std::string out = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\')
    {
      out += '\\';
      out += c;
    }
    else if (static_cast<unsigned char>(c) < 0x20)
    {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
    }
    else
      out += c;
  }
  return out + "\"";
}

std::string num(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}
}  // namespace

std::string toJson(const CalibrationSummary& s)
{
  std::ostringstream o;
  o << "{\"windows\":" << s.windows << ",\"detections\":" << s.detections << ",\"views_collected\":" << s.views_collected;
  if (s.result)
  {
    const CalibrationResult& r = *s.result;
    const CameraIntrinsics& k = r.camera.intrinsics();
    o << ",\"views_used\":" << r.used_views.size() << ",\"views_dropped\":" << r.dropped_views.size()
      << ",\"rms_px\":" << num(r.rms_px) << ",\"per_view_rms_px\":[";
    for (size_t i = 0; i < r.per_view_rms_px.size(); ++i)
      o << (i ? "," : "") << num(r.per_view_rms_px[i]);
    o << "],\"width\":" << k.width << ",\"height\":" << k.height << ",\"fx\":" << num(k.fx) << ",\"fy\":" << num(k.fy)
      << ",\"cx\":" << num(k.cx) << ",\"cy\":" << num(k.cy) << ",\"distortion_model\":\"plumb_bob\",\"distortion\":["
      << num(k.k1) << "," << num(k.k2) << "," << num(k.p1) << "," << num(k.p2) << "," << num(k.k3) << "]";
  }
  if (!s.error.empty())
    o << ",\"error\":" << quoted(s.error);
  if (!s.output_path.empty())
    o << ",\"out\":" << quoted(s.output_path);
  o << "}";
  return o.str();
}
}  // namespace dvs_calibration
