#pragma once
// A planar scene on a wall: the world plane z = 0 (world x right, y up on the wall, z out of the
// wall towards the camera). The wall has a uniform background reflectance; on it lie polygons
// with their own reflectance, each optionally modulated in time (an emissive screen: a square-
// wave flicker, a sine, or any callback). Polygons are painted in order; a polygon must either
// not overlap the earlier ones or lie entirely inside one earlier polygon (nesting, e.g. a
// white disc on a black board). Rendering is then exact (area-correct) for every pixel.
//
// Intensities are linear in [0, 1] (irradiance = reflectance for a unit, uniform illumination).
#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace dvs_screen_sim
{
class SceneError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// How a polygon's intensity varies in time.
struct IntensityModulation
{
  enum class Type
  {
    Constant,  ///< always `reflectance`
    Square,    ///< `high` during the first duty fraction of each period, else `low`
    Sine,      ///< low + (high - low) * (1 + sin(2 pi f t + phase)) / 2
    Callback,  ///< `callback(t)` (sampling bounded by the simulator's max_dt)
  };
  Type type = Type::Constant;
  double frequency_hz = 200.0;
  double phase = 0.0;  ///< [rad] for Sine; for Square: fraction of a period the wave is delayed
  double low = 0.1;
  double high = 0.9;
  double duty = 0.5;
  std::function<double(double)> callback;

  /// Intensity at time t (right-continuous at square-wave edges).
  double valueAt(double t, double constant_reflectance) const;
  /// The first time strictly after t where the intensity jumps (Square), +inf otherwise.
  double nextDiscontinuity(double t) const;
};

struct ScenePolygon
{
  std::string name;
  std::vector<Eigen::Vector2d> vertices;  ///< on the wall, (x, y) [m], either orientation
  double reflectance = 0.1;               ///< used when the modulation is Constant
  IntensityModulation modulation;
  bool in_map = true;                     ///< its edges go into the tracker's line map
};

/// An emissive image on the wall (a screen, a printed texture): a rectangle showing a grey-level
/// image (texels row-major, row 0 at the top, linear intensity in [0, 1]) scaled by `gain`
/// (e.g. a backlight flickering at 200 Hz). Optionally its content changes at a fixed refresh
/// period (a monitor): `update(frame_index, texels)` is called whenever floor(t / update_period)
/// changes. Images are drawn on top of the polygons and must not overlap them or each other;
/// a pixel's intensity integrates the image over the pixel's footprint (supersampled, with at
/// least 2 x 2 samples per texel spanned). Images have no edges in the line map.
struct SceneImage
{
  std::string name;
  std::string file;                          ///< where the texels came from (for the config)
  Eigen::Vector2d top_left{-0.5, 0.5};       ///< wall coordinates of the image's top-left corner [m]
  Eigen::Vector2d size{1.0, 1.0};            ///< width (along +x) and height (along -y) [m]
  int width = 0;                             ///< texels per row
  int height = 0;                            ///< rows
  std::vector<float> texels;                 ///< width * height, row-major, [0, 1]
  IntensityModulation gain;                  ///< multiplies the texels; Constant uses `gain_value`
  double gain_value = 1.0;
  double update_period = 0.0;                ///< [s], 0: the content never changes
  /// [s] a monitor's response time: after each content update the luminance moves linearly from
  /// the old to the new texels over this time (in [0, update_period]; 0: instantaneous). The
  /// simulator times the events of an update along that ramp (exact while the camera does not
  /// move relative to the image during the transition).
  double response_time = 0.0;
  std::function<void(int64_t frame_index, std::vector<float>& texels)> update;

  double gainAt(double t) const { return gain.valueAt(t, gain_value); }
};

/// Load a grey-level image file (PNG, PGM, ... via OpenCV) as texels in [0, 1]. Throws
/// SceneError naming the file.
void loadImageTexels(const std::string& path, SceneImage& image);

struct Scene
{
  double background_reflectance = 0.9;
  std::vector<ScenePolygon> polygons;
  std::vector<SceneImage> images;
  Eigen::Vector3d map_up{0.0, 1.0, 0.0};  ///< world direction that is "up" in the image at start

  /// Validates (>= 3 vertices, finite, intensities in [0, 1]) and computes the nesting; call
  /// after editing `polygons`. Throws SceneError naming the polygon.
  void finalize();
  bool timeVarying() const;
  /// Intensity of polygon k at time t.
  double polygonIntensity(size_t k, double t) const;
  /// Intensity of whatever lies directly under polygon k (the wall or its enclosing polygon).
  double underIntensity(size_t k, double t) const;
  /// The earliest intensity jump strictly after t over all polygons (+inf if none).
  double nextDiscontinuity(double t) const;
  /// Enclosing polygon index per polygon (-1: the wall). Valid after finalize().
  const std::vector<int>& parents() const { return parents_; }

private:
  std::vector<int> parents_;
};

/// The thesis target: a 0.9 m x 0.9 m black square (reflectance 0.1) centred at the origin on
/// a white wall (0.9); map up = +y.
Scene defaultSquareScene(double side = 0.9, double square_reflectance = 0.1, double wall_reflectance = 0.9);

/// A grid of circles (regular `circle_vertices`-gons) on a board, e.g. a calibration screen:
/// rows x cols circles of `diameter` at `spacing` (centre to centre), centred on the origin.
Scene circleGridScene(int rows, int cols, double spacing, double diameter, double circle_intensity,
                      double board_intensity, int circle_vertices = 48);

/// Scene from YAML: {background_reflectance, map_up: [x,y,z], polygons: [{name, reflectance,
/// vertices: [[x,y],...], in_map, modulation: {type: constant|square|sine, frequency_hz,
/// phase, low, high, duty}}], images: [{name, file, top_left: [x,y], size: [w,h], gain,
/// modulation: {...}}]}. Throws SceneError naming the offending key.
Scene sceneFromYaml(const YAML::Node& node);
YAML::Node sceneToYaml(const Scene& scene);
Scene loadSceneYaml(const std::string& path);

/// A 3D line segment of the map (world frame).
struct MapSegment
{
  Eigen::Vector3d a, b;
};
/// Every edge of every polygon with in_map set.
std::vector<MapSegment> mapSegments(const Scene& scene);
/// The tracker's line map YAML (frame_id world, up, segments); see formats.md.
void writeLineMapYaml(const std::string& path, const Scene& scene);
}  // namespace dvs_screen_sim
