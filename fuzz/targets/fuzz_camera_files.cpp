// Camera files: the first byte chooses calib.txt or camera_info YAML; the rest is the file.
#include <dvs_calibration/camera_model.h>

#include "temp_file.h"

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  if (size < 1)
    return 0;
  const bool yaml = data[0] & 1;
  const std::string path = fuzz::writeTemp(data + 1, size - 1, yaml ? ".yaml" : ".txt");
  try
  {
    const dvs_calibration::CameraModel camera = dvs_calibration::loadCameraFile(path, 128, 128);
    // An accepted model must undistort every pixel to a finite position.
    for (int y = 0; y < camera.height(); y += 7)
      for (int x = 0; x < camera.width(); x += 7)
        if (!camera.undistortedPixelLut(x, y).allFinite())
          std::abort();
  }
  catch (const std::exception&)
  {
  }
  return 0;
}
