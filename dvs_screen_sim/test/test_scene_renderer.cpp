#include <dvs_screen_sim/scene_renderer.h>
#include <dvs_screen_sim/trajectory.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <unistd.h>

using namespace dvs_screen_sim;

namespace
{
dvs_calibration::CameraModel pinhole(int w = 32, int h = 32, double f = 50)
{
  dvs_calibration::CameraIntrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = f;
  k.cx = (w - 1) / 2.0;
  k.cy = (h - 1) / 2.0;
  return dvs_calibration::CameraModel(k);
}

Pose facingWall(double x, double y, double d)
{
  const Pose p = Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(x, y, d));
  return p;
}

Scene rectangleScene(double x0, double y0, double x1, double y1, double r = 0.1, double bg = 0.9)
{
  Scene s;
  s.background_reflectance = bg;
  ScenePolygon p;
  p.reflectance = r;
  p.vertices = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  s.polygons.push_back(p);
  s.finalize();
  return s;
}
}  // namespace

TEST(SceneRenderer, EdgeCoverageIsExactAtSubPixelOffsets)
{
  const auto cam = pinhole();
  // Black region to the right of world x = e (covers the right part of the image).
  for (double e_px = 0.0; e_px < 1.0; e_px += 0.1)
  {
    const double e = (e_px - 0.5) / 50.0;  // image column of the edge = cx + 50 e = 15 + e_px
    SceneRenderer r(cam, rectangleScene(e, -10, 10, 10));
    r.setState(facingWall(0, 0, 1), 0);
    const double u = 15.5 + 50 * e;
    for (int c = 13; c <= 18; ++c)
    {
      const double frac = std::clamp(c + 0.5 - u, 0.0, 1.0);
      EXPECT_NEAR(r.pixelIntensity(c, 10), 0.9 + (0.1 - 0.9) * frac, 1e-9) << "col " << c << " edge " << u;
    }
  }
}

TEST(SceneRenderer, TotalDarknessEqualsProjectedArea)
{
  const auto cam = pinhole(64, 64, 60);
  const Scene scene = rectangleScene(-0.2, -0.15, 0.25, 0.2);
  SceneRenderer r(cam, scene);
  const Pose pose = Pose::fromWorldCamera(orientationFromYawPitchRollDeg({8, -5, 33}), Eigen::Vector3d(0.05, -0.02, 1.2));
  r.setState(pose, 0);
  std::vector<double> img;
  r.renderImage(img);
  double dark = 0;
  for (double v : img)
    dark += 0.9 - v;
  // Known answer: the projected quadrilateral's area (shoelace of the projected corners).
  double area = 0;
  const auto& v = scene.polygons[0].vertices;
  for (size_t i = 0; i < 4; ++i)
  {
    Eigen::Vector2d a, b;
    ASSERT_TRUE(cam.projectIdeal(pose.toCamera({v[i].x(), v[i].y(), 0}), a));
    ASSERT_TRUE(cam.projectIdeal(pose.toCamera({v[(i + 1) % 4].x(), v[(i + 1) % 4].y(), 0}), b));
    ASSERT_TRUE(cam.inImage(a, 1) && cam.inImage(b, 1));
    area += a.x() * b.y() - a.y() * b.x();
  }
  area = std::abs(area) / 2;
  EXPECT_NEAR(dark, 0.8 * area, 1e-6 * area);
}

TEST(SceneRenderer, NestedPolygonsAndBehindCamera)
{
  const auto cam = pinhole();
  Scene s = rectangleScene(-0.3, -0.3, 0.3, 0.3, 0.1, 0.5);
  ScenePolygon inner;
  inner.reflectance = 0.8;
  inner.vertices = {{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {-0.1, 0.1}};
  s.polygons.push_back(inner);
  s.finalize();
  ASSERT_EQ(s.parents()[1], 0);
  SceneRenderer r(cam, s);
  r.setState(facingWall(0, 0, 1), 0);
  EXPECT_NEAR(r.pixelIntensity(15, 15), 0.8, 1e-12);  // inner (0.1 m = 5 px)
  EXPECT_NEAR(r.pixelIntensity(15, 15 - 10), 0.1, 1e-12);  // ring
  EXPECT_NEAR(r.pixelIntensity(0, 0), 0.5, 1e-12);  // wall (corner at 0.31 m)
  // Camera turned away from the wall: its polygons are behind; the wall's level everywhere.
  const Pose away = Pose::fromWorldCamera(Eigen::Quaterniond::Identity(), facingWall(0, 0, 1).p_world_camera());  // looking along +z, away from the wall
  r.setState(away, 0);
  EXPECT_NEAR(r.pixelIntensity(15, 15), 0.5, 1e-12);
}

TEST(SceneRenderer, EdgeBandContainsEveryMixedPixelWithDistortion)
{
  const auto cam = dvs_calibration::CameraModel::dvs128();
  ASSERT_TRUE(cam.hasDistortion());
  const Scene scene = defaultSquareScene();
  SceneRenderer r(cam, scene);
  FlipTrajectoryParams fp;
  const FlipTrajectory flip(fp);
  std::vector<uint32_t> marks(128 * 128, 0);
  uint32_t mark = 0;
  for (double t : {0.0, 0.7, 0.75, 0.8})
  {
    r.setState(flip.poseAt(t), t);
    std::vector<int32_t> band;
    r.appendEdgePixels(band, marks, ++mark);
    std::vector<double> img;
    r.renderImage(img);
    int mixed = 0;
    for (int i = 0; i < 128 * 128; ++i)
      if (std::abs(img[i] - 0.1) > 1e-9 && std::abs(img[i] - 0.9) > 1e-9)
      {
        ++mixed;
        EXPECT_EQ(marks[i], mark) << "mixed pixel " << i % 128 << "," << i / 128 << " not in the band at t=" << t;
      }
    EXPECT_GT(mixed, 100);
    EXPECT_LT(band.size(), 4u * mixed);  // a band, not the image
  }
}

TEST(SceneRenderer, MaxImageMotionOfATranslation)
{
  const auto cam = pinhole(64, 64, 60);
  SceneRenderer r(cam, rectangleScene(-0.2, -0.2, 0.2, 0.2));
  r.setState(facingWall(0, 0, 1.5), 0);
  EXPECT_NEAR(r.maxImageMotion(facingWall(0.01, 0, 1.5)), 60 * 0.01 / 1.5, 1e-6);
  EXPECT_NEAR(r.maxImageMotion(facingWall(0, 0, 1.5)), 0.0, 1e-12);
}

TEST(SceneModulation, SquareWaveEdgesAndValues)
{
  IntensityModulation m;
  m.type = IntensityModulation::Type::Square;
  m.frequency_hz = 200;
  m.low = 0.2;
  m.high = 0.7;
  EXPECT_DOUBLE_EQ(m.valueAt(0.001, 0), 0.7);
  EXPECT_DOUBLE_EQ(m.valueAt(0.0035, 0), 0.2);
  EXPECT_DOUBLE_EQ(m.valueAt(0.0025, 0), 0.2);  // right-continuous at the falling edge
  EXPECT_DOUBLE_EQ(m.valueAt(0.005, 0), 0.7);   // and at the rising edge
  EXPECT_NEAR(m.nextDiscontinuity(0.001), 0.0025, 1e-12);
  EXPECT_NEAR(m.nextDiscontinuity(0.0025), 0.005, 1e-12);
}

TEST(Scene, YamlRoundTripAndErrors)
{
  const Scene grid = circleGridScene(2, 3, 0.1, 0.05, 0.9, 0.1, 16);
  const Scene back = sceneFromYaml(sceneToYaml(grid));
  ASSERT_EQ(back.polygons.size(), 6u);
  EXPECT_EQ(back.polygons[4].vertices.size(), 16u);
  EXPECT_FALSE(back.polygons[0].in_map);
  EXPECT_THROW(sceneFromYaml(YAML::Load("polygons: [{vertices: [[0,0],[1,0]]}]")), SceneError);
  EXPECT_THROW(sceneFromYaml(YAML::Load("polygons: [{vertices: [[0,0],[1,0],[1,1]], reflectance: 2}]")), SceneError);
  EXPECT_THROW(sceneFromYaml(YAML::Load("polygons: [{vertices: [[0,0],[1,0],[1,1]], colour: 1}]")), SceneError);
  EXPECT_EQ(mapSegments(defaultSquareScene()).size(), 4u);
}

TEST(SceneRenderer, EmissiveImageIsIntegratedOverThePixelFootprint)
{
  const auto cam = pinhole(32, 32, 50);
  Scene s;
  s.background_reflectance = 0.3;
  SceneImage im;
  im.width = 2;
  im.height = 1;
  im.texels = {0.0f, 1.0f};
  im.top_left = Eigen::Vector2d(-0.2, 0.1);  // 0.4 m x 0.2 m: 20 x 10 px at 1 m, centred
  im.size = Eigen::Vector2d(0.4, 0.2);
  s.images.push_back(im);
  s.finalize();
  SceneRenderer r(cam, s);
  ASSERT_TRUE(r.hasImages());
  r.setState(facingWall(0, 0, 1), 0);
  // Image spans columns 5.5 .. 25.5 (texel boundary at 15.5) and rows 10.5 .. 20.5.
  EXPECT_NEAR(r.pixelIntensity(10, 15), 0.0, 1e-12);
  EXPECT_NEAR(r.pixelIntensity(20, 15), 1.0, 1e-12);
  EXPECT_NEAR(r.pixelIntensity(2, 15), 0.3, 1e-12);   // wall
  EXPECT_NEAR(r.pixelIntensity(20, 5), 0.3, 1e-12);
  // Shift by half a pixel: pixel 15 straddles the texel boundary, pixel 5 the image border.
  r.setState(facingWall(0.01, 0, 1), 0);  // 0.5 px
  EXPECT_NEAR(r.pixelIntensity(15, 15), 0.5, 1e-12);
  EXPECT_NEAR(r.pixelIntensity(5, 15), 0.15, 1e-12);  // half wall (0.3), half black texel
  // Gain modulation scales the image.
  s.images[0].gain.type = IntensityModulation::Type::Square;
  s.images[0].gain.low = 0.25;
  s.images[0].gain.high = 0.5;
  SceneRenderer r2(cam, s);
  r2.setState(facingWall(0, 0, 1), 0.001);
  EXPECT_NEAR(r2.pixelIntensity(20, 15), 0.5, 1e-12);
  r2.setState(facingWall(0, 0, 1), 0.003);
  EXPECT_NEAR(r2.pixelIntensity(20, 15), 0.25, 1e-12);
}

TEST(Scene, ImagesLoadFromYamlAndFiles)
{
  const std::string path = "/tmp/dvs_screen_sim_test_texture_" + std::to_string(::getpid()) + ".pgm";
  {
    std::ofstream f(path, std::ios::binary);
    f << "P5\n2 2\n255\n";
    const unsigned char px[4] = {0, 255, 51, 102};
    f.write(reinterpret_cast<const char*>(px), 4);
  }
  const Scene s = sceneFromYaml(YAML::Load("{polygons: [], images: [{name: screen, file: " + path +
                                           ", top_left: [-0.3, 0.2], size: [0.6, 0.4], gain: 0.5}]}"));
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].width, 2);
  EXPECT_NEAR(s.images[0].texels[1], 1.0, 1e-6);
  EXPECT_NEAR(s.images[0].texels[2], 0.2, 1e-6);
  EXPECT_DOUBLE_EQ(s.images[0].gain_value, 0.5);
  const Scene back = sceneFromYaml(sceneToYaml(s));
  EXPECT_EQ(back.images[0].texels, s.images[0].texels);
  EXPECT_THROW(sceneFromYaml(YAML::Load("{images: [{file: /nonexistent.png}]}")), SceneError);
  EXPECT_THROW(sceneFromYaml(YAML::Load("{images: [{file: " + path + ", size: [0, 1]}]}")), SceneError);
  std::remove(path.c_str());
}

TEST(SceneRenderer, MatchesBruteForceSupersamplingWithDistortion)
{
  // Independent reference: 32 x 32 sample points per sensor pixel, each undistorted, cast to the
  // wall and tested against the square (point in polygon).
  const auto cam = dvs_calibration::CameraModel::davis240();  // strong distortion
  const Scene scene = defaultSquareScene();
  SceneRenderer r(cam, scene);
  FlipTrajectoryParams fp;
  fp.distance = 1.2;
  const FlipTrajectory flip(fp);
  for (double t : {0.70, 0.76})
  {
    const Pose pose = flip.poseAt(t);
    r.setState(pose, t);
    int compared = 0;
    for (int y = 0; y < cam.height(); y += 3)
      for (int x = 0; x < cam.width(); x += 3)
      {
        const double v = r.pixelIntensity(x, y);
        if (std::abs(v - 0.1) < 1e-12 || std::abs(v - 0.9) < 1e-12)
          continue;  // compare mixed pixels only (the others are checked by the band test)
        const int n = 32;
        int inside = 0;
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i)
          {
            const Eigen::Vector2d xn =
                cam.pixelToUndistortedNormalized(Eigen::Vector2d(x - 0.5 + (i + 0.5) / n, y - 0.5 + (j + 0.5) / n));
            const Eigen::Vector3d d = pose.q_world_camera() * Eigen::Vector3d(xn.x(), xn.y(), 1.0);
            const Eigen::Vector3d w = pose.p_world_camera() + (-pose.p_world_camera().z() / d.z()) * d;
            inside += std::abs(w.x()) < 0.45 && std::abs(w.y()) < 0.45;
          }
        const double reference = 0.9 - 0.8 * inside / double(n * n);
        EXPECT_NEAR(v, reference, 0.8 * 0.02) << x << "," << y << " t=" << t;
        ++compared;
      }
    EXPECT_GT(compared, 20);
  }
}
