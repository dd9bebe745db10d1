// Fullscreen display of the focus pattern (thesis Fig. 2.1a) or the calibration grid (Fig. 2.1b),
// static (for a dimmed, flickering LED backlight) or blinking in software (for screens that do
// not flicker). Prints the physical dot spacing to pass to the calibrator.
#include <dvs_calibration/event_image.h>
#include <dvs_calibration/pattern_renderer.h>

#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <thread>

namespace
{
const char* kUsage = R"(usage: show_pattern [--pattern grid|focus] [--grid CxR] [--spacing-px PX] [--radius-fraction F]
                    [--border PX] [--blink-hz HZ] [--focus-step S] [--screen-width-mm MM | --dpi DPI]
                    [--resolution WxH] [--windowed] [--frames N] [--save FILE.png]
  --pattern grid|focus   calibration grid of white circles on black (default) or the focus pattern
  --grid CxR             circles, columns x rows (default 7x7)
  --spacing-px PX        centre-to-centre distance in screen pixels (default: the largest that fits)
  --radius-fraction F    circle radius / spacing (default 0.3)
  --border PX            black margin around the grid (default 40)
  --blink-hz HZ          blink the pattern on/off at HZ full periods per second (default 0 = static,
                         for a dimmed screen whose backlight flickers)
  --focus-step S         size ratio of neighbouring focus squares (default 0.8)
  --screen-width-mm MM   visible width of the screen, to print the dot spacing in metres
  --dpi DPI              or the screen's dots per inch
  --resolution WxH       screen size when the window system does not report it (default 1920x1080)
  --windowed             a normal window instead of fullscreen
  --frames N             quit after N displayed frames (for tests); 0 = run until q/Esc
  --save FILE.png        write the pattern image and quit (no window)
keys: q/Esc quit, g grid, f focus pattern, b blinking on/off
)";

bool parseSize(const std::string& s, int& w, int& h)
{
  const size_t x = s.find('x');
  if (x == std::string::npos)
    return false;
  char* e1 = nullptr;
  char* e2 = nullptr;
  const std::string a = s.substr(0, x), b = s.substr(x + 1);
  w = static_cast<int>(std::strtol(a.c_str(), &e1, 10));
  h = static_cast<int>(std::strtol(b.c_str(), &e2, 10));
  return !a.empty() && !b.empty() && *e1 == '\0' && *e2 == '\0' && w > 0 && h > 0;
}

double number(const std::map<std::string, std::string>& args, const std::string& key, double def)
{
  auto it = args.find(key);
  if (it == args.end())
    return def;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end != '\0')
    throw std::invalid_argument("--" + key + " '" + it->second + "' is not a number");
  return v;
}

void printSpacing(const dvs_calibration::CircleGridPattern& p, int w, int h, double pitch_mm)
{
  const double s = dvs_calibration::circleGridSpacingPx(w, h, p);
  if (pitch_mm > 0)
  {
    const double m = s * pitch_mm / 1000.0;
    std::printf("dot spacing: %.0f screen pixels = %.2f mm -> calibrate with --spacing %.5f\n", s, s * pitch_mm, m);
  }
  else
    std::printf("dot spacing: %.0f screen pixels. Measure the distance between the centres of the first and the\n"
                "last circle of a row (metres) and divide it by %d: that is --spacing. (Or pass --screen-width-mm.)\n",
                s, p.grid.cols - 1);
  std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv)
{
  using namespace dvs_calibration;
  std::map<std::string, std::string> args;
  const std::map<std::string, bool> known = {{"pattern", true},  {"grid", true},       {"spacing-px", true},
                                             {"radius-fraction", true}, {"border", true}, {"blink-hz", true},
                                             {"focus-step", true}, {"screen-width-mm", true}, {"dpi", true},
                                             {"resolution", true}, {"windowed", false}, {"frames", true},
                                             {"save", true},       {"help", false}};
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0 || !known.count(a.substr(2)))
    {
      std::cerr << "show_pattern: unknown argument '" << a << "'\n" << kUsage;
      return 2;
    }
    if (known.at(a.substr(2)))
    {
      if (i + 1 >= argc)
      {
        std::cerr << "show_pattern: " << a << " needs a value\n";
        return 2;
      }
      args[a.substr(2)] = argv[++i];
    }
    else
      args[a.substr(2)] = "1";
  }
  if (args.count("help"))
  {
    std::cout << kUsage;
    return 0;
  }

  CircleGridPattern grid;
  std::string pattern = args.count("pattern") ? args["pattern"] : "grid";
  double blink_hz = 0, focus_step = 0.8, pitch_mm = 0;
  int width = 1920, height = 1080;
  long frames = 0;
  try
  {
    if (pattern != "grid" && pattern != "focus")
      throw std::invalid_argument("--pattern must be grid or focus, got '" + pattern + "'");
    if (args.count("grid"))
      grid.grid = parseGridSize(args["grid"]);
    grid.spacing_px = number(args, "spacing-px", 0);
    grid.radius_fraction = number(args, "radius-fraction", 0.3);
    grid.border_px = static_cast<int>(number(args, "border", 40));
    blink_hz = number(args, "blink-hz", 0);
    if (blink_hz < 0 || blink_hz > 120)
      throw std::invalid_argument("--blink-hz must be in [0, 120]");
    focus_step = number(args, "focus-step", 0.8);
    frames = static_cast<long>(number(args, "frames", 0));
    if (args.count("resolution") && !parseSize(args["resolution"], width, height))
      throw std::invalid_argument("--resolution must be WIDTHxHEIGHT, got '" + args["resolution"] + "'");
    pitch_mm = screenPixelPitchMm(number(args, "screen-width-mm", 0), width, number(args, "dpi", 0));
  }
  catch (const std::exception& e)
  {
    std::cerr << "show_pattern: " << e.what() << "\n";
    return 2;
  }

  const auto render = [&](const std::string& which, int w, int h) {
    return which == "focus" ? renderFocusPattern(w, h, focus_step, 0) : renderCircleGrid(w, h, grid);
  };

  if (args.count("save"))
  {
    try
    {
      const cv::Mat img = render(pattern, width, height);
      dvs_calibration::writeImageChecked(args["save"], img);
      if (pattern == "grid")
        printSpacing(grid, width, height, pitch_mm);
    }
    catch (const std::exception& e)
    {
      std::cerr << "show_pattern: " << e.what() << "\n";
      return 2;
    }
    return 0;
  }

  const std::string win = "dvs_calibration pattern";
  cv::namedWindow(win, cv::WINDOW_NORMAL);
  if (!args.count("windowed"))
    cv::setWindowProperty(win, cv::WND_PROP_FULLSCREEN, cv::WINDOW_FULLSCREEN);
  cv::imshow(win, cv::Mat::zeros(height, width, CV_8U));
  // The window system's idea of the screen size once the window is fullscreen (it takes a few
  // event-loop turns); drawn 1:1 in screen pixels so the printed spacing is exact.
  cv::Rect r;
  for (int i = 0; i < 10; ++i)
  {
    cv::waitKey(50);
    r = cv::getWindowImageRect(win);
  }
  if (!args.count("windowed") && !args.count("resolution") && r.width >= 640 && r.height >= 480)
  {
    width = r.width;
    height = r.height;
    pitch_mm = screenPixelPitchMm(number(args, "screen-width-mm", 0), width, number(args, "dpi", 0));
  }
  cv::Mat shown, black = cv::Mat::zeros(height, width, CV_8U);
  try
  {
    shown = render(pattern, width, height);
  }
  catch (const std::exception& e)
  {
    std::cerr << "show_pattern: " << e.what() << "\n";
    return 2;
  }
  std::printf("showing the %s pattern at %dx%d, %s\n", pattern.c_str(), width, height,
              blink_hz > 0 ? ("blinking at " + std::to_string(blink_hz) + " Hz").c_str() : "static");
  if (pattern == "grid")
    printSpacing(grid, width, height, pitch_mm);

  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  bool blinking = blink_hz > 0;
  if (!blinking)
    blink_hz = 10;  // rate used if blinking is switched on with 'b'
  for (long frame = 0; frames == 0 || frame < frames; ++frame)
  {
    bool on = true;
    int wait_ms = 30;
    if (blinking)
    {
      const double half = 0.5 / blink_hz;
      const double t = std::chrono::duration<double>(clock::now() - t0).count();
      on = static_cast<long>(t / half) % 2 == 0;
      wait_ms = std::max(1, static_cast<int>(((std::floor(t / half) + 1) * half - t) * 1000));
    }
    cv::imshow(win, on ? shown : black);
    const int key = cv::waitKey(wait_ms);
    if (key == 'q' || key == 27)
      break;
    if (key == 'g' || key == 'f')
    {
      pattern = key == 'g' ? "grid" : "focus";
      try
      {
        shown = render(pattern, width, height);
      }
      catch (const std::exception& e)
      {
        std::cerr << "show_pattern: " << e.what() << "\n";
      }
      if (pattern == "grid")
        printSpacing(grid, width, height, pitch_mm);
    }
    if (key == 'b')
      blinking = !blinking;
  }
  cv::destroyAllWindows();
  return 0;
}
