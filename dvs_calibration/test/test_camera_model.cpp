#include <dvs_calibration/camera_model.h>
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>

#include <cstdio>
#include <fstream>
#include <random>
#include <unistd.h>

using dvs_calibration::CameraIntrinsics;
using dvs_calibration::CameraModel;
using dvs_calibration::CameraModelError;

namespace
{
std::string tempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }
}  // namespace

TEST(CameraModel, ProjectionMatchesOpenCv)
{
  for (const CameraModel& cam : {CameraModel::dvs128(), CameraModel::davis240(), CameraModel::davis346()})
  {
    const CameraIntrinsics& k = cam.intrinsics();
    const cv::Mat K = (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    const cv::Mat D = (cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::vector<cv::Point3d> pts;
    for (int i = 0; i < 200; ++i)
      pts.emplace_back(u(rng), u(rng), 1.0 + u(rng));
    std::vector<cv::Point2d> cv_px;
    cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, cv_px);
    for (size_t i = 0; i < pts.size(); ++i)
    {
      Eigen::Vector2d px;
      ASSERT_TRUE(cam.project(Eigen::Vector3d(pts[i].x, pts[i].y, pts[i].z), px));
      EXPECT_NEAR(cv_px[i].x, px.x(), 1e-9);
      EXPECT_NEAR(cv_px[i].y, px.y(), 1e-9);
    }
  }
}

TEST(CameraModel, UndistortInvertsDistortAcrossTheSensor)
{
  for (const CameraModel& cam : {CameraModel::dvs128(), CameraModel::davis240(), CameraModel::davis346()})
  {
    for (int y = 0; y < cam.height(); y += 7)
      for (int x = 0; x < cam.width(); x += 7)
      {
        const Eigen::Vector2d px(x, y);
        const Eigen::Vector2d ideal = cam.undistortPixel(px);
        EXPECT_LT((cam.distortPixel(ideal) - px).norm(), 1e-8) << "pixel " << x << "," << y;
      }
  }
}

TEST(CameraModel, UndistortMatchesOpenCv)
{
  const CameraModel cam = CameraModel::davis240();
  const CameraIntrinsics& k = cam.intrinsics();
  const cv::Mat K = (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3);
  std::vector<cv::Point2d> in{{10, 10}, {120, 90}, {230, 170}, {5, 170}}, out;
  cv::undistortPoints(in, out, K, D, cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  for (size_t i = 0; i < in.size(); ++i)
  {
    const Eigen::Vector2d ideal = cam.undistortPixel(Eigen::Vector2d(in[i].x, in[i].y));
    EXPECT_NEAR(out[i].x, ideal.x(), 1e-3);
    EXPECT_NEAR(out[i].y, ideal.y(), 1e-3);
  }
}

TEST(CameraModel, LookupTableEqualsUndistortPixel)
{
  const CameraModel cam = CameraModel::dvs128();
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x)
    {
      const Eigen::Vector2d ideal = cam.undistortPixel(Eigen::Vector2d(x, y));
      ASSERT_NEAR(ideal.x(), cam.undistortedPixelLut(x, y).x(), 1e-4);
      ASSERT_NEAR(ideal.y(), cam.undistortedPixelLut(x, y).y(), 1e-4);
    }
  // Distortion moves the corners (barrel: towards the centre when undistorting is outwards).
  EXPECT_GT((cam.undistortedPixelLut(0, 0).cast<double>() - Eigen::Vector2d(0, 0)).norm(), 1.0);
}

TEST(CameraModel, PointBehindCameraDoesNotProject)
{
  const CameraModel cam;
  Eigen::Vector2d px(-7, -7);
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.1, 0.1, -1.0), px));
  EXPECT_EQ(-7, px.x());
  EXPECT_TRUE(cam.project(Eigen::Vector3d(0, 0, 2.0), px));
  EXPECT_NEAR(cam.intrinsics().cx, px.x(), 1e-12);
}

TEST(CameraModel, InvalidIntrinsicsAreRejected)
{
  CameraIntrinsics k = CameraModel::dvs128().intrinsics();
  k.fx = -1;
  EXPECT_THROW(CameraModel{k}, CameraModelError);
  k = CameraModel::dvs128().intrinsics();
  k.width = 0;
  EXPECT_THROW(CameraModel{k}, CameraModelError);
  EXPECT_THROW(CameraModel::preset("kinect"), CameraModelError);
  EXPECT_EQ(240, CameraModel::preset("DAVIS240").width());
}

TEST(CameraModel, CalibTxtRoundTrip)
{
  const std::string path = tempPath("calib.txt");
  saveCalibTxt(path, CameraModel::davis240());
  const CameraModel back = dvs_calibration::loadCalibTxt(path, 240, 180);
  EXPECT_EQ(CameraModel::davis240().distortionCoefficients(), back.distortionCoefficients());
  EXPECT_EQ(CameraModel::davis240().cameraMatrix(), back.cameraMatrix());
  std::remove(path.c_str());
}

TEST(CameraModel, CalibTxtErrorsNameTheFile)
{
  const std::string path = tempPath("bad_calib.txt");
  {
    std::ofstream(path) << "100 100 abc 64\n";
  }
  try
  {
    dvs_calibration::loadCalibTxt(path);
    FAIL() << "accepted a malformed calib.txt";
  }
  catch (const CameraModelError& e)
  {
    EXPECT_NE(std::string::npos, std::string(e.what()).find("bad_calib.txt")) << e.what();
  }
  {
    std::ofstream(path) << "100 100 64\n";
  }
  EXPECT_THROW(dvs_calibration::loadCalibTxt(path), CameraModelError);
  EXPECT_THROW(dvs_calibration::loadCalibTxt("/nonexistent/calib.txt"), CameraModelError);
  std::remove(path.c_str());
}

TEST(CameraModel, CameraInfoYamlRoundTrip)
{
  const std::string path = tempPath("camera.yaml");
  saveCameraInfoYaml(path, CameraModel::davis346(), "DVS128-0042");
  std::string name;
  const CameraModel back = dvs_calibration::loadCameraInfoYaml(path, &name);
  EXPECT_EQ("DVS128-0042", name);
  EXPECT_EQ(346, back.width());
  EXPECT_EQ(260, back.height());
  EXPECT_TRUE(back.distortionCoefficients().isApprox(CameraModel::davis346().distortionCoefficients(), 1e-12));
  EXPECT_TRUE(back.cameraMatrix().isApprox(CameraModel::davis346().cameraMatrix(), 1e-12));
  {
    std::ofstream(path) << "image_width: 128\ncamera_matrix: {rows: 3, cols: 3, data: [1, 2]}\n";
  }
  EXPECT_THROW(dvs_calibration::loadCameraInfoYaml(path), CameraModelError);
  std::remove(path.c_str());
}

TEST(CameraModelValidation, AbsurdIntrinsicsAreRefusedWithTheReason)
{
  auto make = [](auto edit) {
    dvs_calibration::CameraIntrinsics k = dvs_calibration::CameraModel::dvs128().intrinsics();
    edit(k);
    return k;
  };
  auto expectError = [](const dvs_calibration::CameraIntrinsics& k, const std::string& part) {
    try
    {
      dvs_calibration::CameraModel m(k);
      ADD_FAILURE() << "accepted, expected an error with '" << part << "'";
    }
    catch (const dvs_calibration::CameraModelError& e)
    {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError(make([](auto& k) { k.cx = 1e9; }), "principal point");
  expectError(make([](auto& k) { k.width = k.height = 60000; }), "its undistortion table would take 28800 MB");
  expectError(make([](auto& k) { k.k1 = 1e6; }), "shrinks the sensor's field of view");
  expectError(make([](auto& k) { k.k1 = -2.0; }), "folds back");
  expectError(make([](auto& k) { k.p1 = 0.5; }), "tangential");
  // Real lenses pass: the presets and a wide barrel lens (k1 -0.3 at ~75 deg across 240 px).
  EXPECT_NO_THROW(dvs_calibration::CameraModel::davis346());
  EXPECT_NO_THROW(dvs_calibration::CameraModel(make([](auto& k) {
    k.width = 240;
    k.height = 180;
    k.fx = k.fy = 155;
    k.cx = 119.5;
    k.cy = 89.5;
    k.k1 = -0.3;
    k.k2 = 0.08;
  })));
}

TEST(CameraModelValidation, RationalPolynomialTermsAreNotDroppedSilently)
{
  const std::string path = tempPath("rational.yaml");
  std::ofstream(path) << "image_width: 128\nimage_height: 128\ncamera_name: x\n"
                         "camera_matrix: {rows: 3, cols: 3, data: [115, 0, 63.5, 0, 115, 63.5, 0, 0, 1]}\n"
                         "distortion_model: rational_polynomial\n"
                         "distortion_coefficients: {rows: 1, cols: 8, data: [-0.1, 0.01, 0, 0, 0, 0.2, 0, 0]}\n";
  try
  {
    dvs_calibration::loadCameraInfoYaml(path);
    FAIL() << "k4 dropped silently";
  }
  catch (const dvs_calibration::CameraModelError& e)
  {
    EXPECT_NE(std::string(e.what()).find("coefficient 5"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "image_width: 128\nimage_height: 128\ncamera_name: x\n"
                         "camera_matrix: {rows: 3, cols: 3, data: [115, 0, 63.5, 0, 115, 63.5, 0, 0, 1]}\n"
                         "distortion_model: rational_polynomial\n"
                         "distortion_coefficients: {rows: 1, cols: 8, data: [-0.1, 0.01, 0, 0, 0, 0, 0, 0]}\n";
  EXPECT_NEAR(dvs_calibration::loadCameraInfoYaml(path).intrinsics().k1, -0.1, 1e-12);
}

TEST(CameraFile, OneRuleForCalibTxtAndYaml)
{
  const dvs_calibration::CameraModel cam = dvs_calibration::CameraModel::davis240();
  const std::string txt = tempPath("rule_calib.txt"), yaml = tempPath("rule_camera.yaml");
  dvs_calibration::saveCalibTxt(txt, cam);
  dvs_calibration::saveCameraInfoYaml(yaml, cam, "davis");
  EXPECT_EQ(dvs_calibration::loadCameraFile(txt, 240, 180).width(), 240);
  EXPECT_EQ(dvs_calibration::loadCameraFile(yaml).height(), 180);
  EXPECT_EQ(dvs_calibration::loadCameraFile(yaml, 240, 180).width(), 240);
  try
  {
    dvs_calibration::loadCameraFile(txt);
    FAIL() << "a calib.txt without a size was accepted";
  }
  catch (const dvs_calibration::CameraModelError& e)
  {
    EXPECT_NE(std::string(e.what()).find("rule_calib.txt: a calib.txt holds no sensor size"), std::string::npos)
        << e.what();
  }
  try
  {
    dvs_calibration::loadCameraFile(yaml, 128, 128);
    FAIL() << "a size contradicting the YAML was accepted";
  }
  catch (const dvs_calibration::CameraModelError& e)
  {
    EXPECT_NE(std::string(e.what()).find("the file says 240x180 pixels but 128x128 was given"), std::string::npos)
        << e.what();
  }
}

TEST(CameraFile, WritesOnAFullDiskAreNamedErrors)
{
  // The calibration result and the simulator's calib files go through the checked writer.
  const std::string link = tempPath("full_camera.yaml");
  std::remove(link.c_str());
  ASSERT_EQ(::symlink("/dev/full", link.c_str()), 0);
  try
  {
    dvs_calibration::saveCameraInfoYaml(link, dvs_calibration::CameraModel::dvs128(), "dvs");
    FAIL() << "a write to a full disk reported success";
  }
  catch (const dvs_calibration::CameraModelError& e)
  {
    EXPECT_NE(std::string(e.what()).find("full_camera.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_THROW(dvs_calibration::saveCalibTxt("/nonexistent_folder_xyz/calib.txt", dvs_calibration::CameraModel::dvs128()),
               dvs_calibration::CameraModelError);
  std::remove(link.c_str());
}
