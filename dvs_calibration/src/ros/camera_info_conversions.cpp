#include <dvs_calibration/camera_info_conversions.h>

namespace dvs_calibration
{
sensor_msgs::CameraInfo toCameraInfoMsg(const CameraModel& camera, const std::string& frame_id)
{
  const CameraIntrinsics& k = camera.intrinsics();
  sensor_msgs::CameraInfo ci;
  ci.header.frame_id = frame_id;
  ci.width = static_cast<uint32_t>(k.width);
  ci.height = static_cast<uint32_t>(k.height);
  ci.distortion_model = "plumb_bob";
  ci.D = {k.k1, k.k2, k.p1, k.p2, k.k3};
  ci.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  ci.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  ci.P = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  return ci;
}

CameraModel cameraFromCameraInfo(const sensor_msgs::CameraInfo& info)
{
  if (!info.D.empty() && info.distortion_model != "plumb_bob")
    throw CameraModelError("camera_info distortion_model '" + info.distortion_model +
                           "' is not supported (use plumb_bob)");
  CameraIntrinsics k;
  k.width = static_cast<int>(info.width);
  k.height = static_cast<int>(info.height);
  k.fx = info.K[0];
  k.fy = info.K[4];
  k.cx = info.K[2];
  k.cy = info.K[5];
  double* const d[5] = {&k.k1, &k.k2, &k.p1, &k.p2, &k.k3};
  for (size_t i = 0; i < info.D.size() && i < 5; ++i)
    *d[i] = info.D[i];
  for (size_t i = 5; i < info.D.size(); ++i)
    if (info.D[i] != 0)
      throw CameraModelError("camera_info D[" + std::to_string(i) + "] is not zero: only plumb_bob's k1 k2 p1 p2 k3 are supported");
  return CameraModel(k);
}
}  // namespace dvs_calibration
