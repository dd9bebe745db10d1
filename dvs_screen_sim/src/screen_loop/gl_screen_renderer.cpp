#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>

#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xatom.h>
#include <X11/Xlib.h>

#include <Eigen/Geometry>

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace dvs_screen_sim
{
namespace screen_loop
{
struct GlScreenRenderer::Impl
{
  Display* display = nullptr;
  Window window = 0;
  Colormap colormap = 0;
  GLXContext context = nullptr;
  Atom wm_delete = 0;
};

bool displayAvailable()
{
  const char* name = std::getenv("DISPLAY");
  if (!name || !*name)
    return false;
  Display* d = XOpenDisplay(nullptr);
  if (!d)
    return false;
  XCloseDisplay(d);
  return true;
}

namespace
{
/// Losing the X server is fatal; Xlib would call exit() from the render thread while other
/// threads (ROS spinners) still run and static destructors race with them: leave at once.
int onDisplayLost(Display*)
{
  static const char msg[] = "screen_loop: lost the X display, exiting\n";
  const ssize_t ignored = write(2, msg, sizeof(msg) - 1);
  (void)ignored;
  _exit(1);
}
}  // namespace

bool reexecUnderXvfbIfNoDisplay(int argc, char** argv)
{
  const char* display = std::getenv("DISPLAY");
  if ((display && *display) || std::getenv("DVS_SCREEN_LOOP_UNDER_XVFB"))
    return true;
  setenv("DVS_SCREEN_LOOP_UNDER_XVFB", "1", 1);
  // -noreset: the server must not reset (and refuse connections meanwhile) whenever its last
  // client disconnects, e.g. between two windows of a test.
  std::vector<std::string> a = {"xvfb-run", "-a", "-n", std::to_string(150 + getpid() % 600), "-s",
                                "-screen 0 1280x1024x24 -noreset"};
  for (int i = 0; i < argc; ++i)
    a.emplace_back(argv[i]);
  std::vector<char*> args;
  for (auto& s : a)
    args.push_back(&s[0]);
  args.push_back(nullptr);
  execvp("xvfb-run", args.data());
  std::fprintf(stderr, "%s: no DISPLAY and cannot run xvfb-run (%s): install xvfb or set DISPLAY\n", argv[0],
               std::strerror(errno));
  return false;
}

GlScreenRenderer::GlScreenRenderer(const WindowConfig& config) : impl_(new Impl)
{
  const char* name = std::getenv("DISPLAY");
  XSetIOErrorHandler(&onDisplayLost);
  impl_->display = XOpenDisplay(nullptr);
  for (int attempt = 0; attempt < 20 && !impl_->display && name && *name; ++attempt)
  {
    usleep(100000);  // a server that is starting or resetting refuses connections for a moment
    impl_->display = XOpenDisplay(nullptr);
  }
  if (!impl_->display)
    throw DisplayError(std::string("cannot open X display '") + (name ? name : "") +
                       "' (set DISPLAY, or run under xvfb-run -a -s \"-screen 0 1280x1024x24\")");
  Display* dpy = impl_->display;
  const int screen = DefaultScreen(dpy);
  int attrs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
  XVisualInfo* vi = glXChooseVisual(dpy, screen, attrs);
  if (!vi)
  {
    XCloseDisplay(dpy);
    impl_->display = nullptr;
    throw DisplayError("no double-buffered 24-bit RGB GLX visual on the X display");
  }
  const Window root = RootWindow(dpy, vi->screen);
  width_ = config.fullscreen ? DisplayWidth(dpy, vi->screen) : config.width;
  height_ = config.fullscreen ? DisplayHeight(dpy, vi->screen) : config.height;
  if (width_ <= 0 || height_ <= 0)
    throw DisplayError("window size must be positive");
  impl_->colormap = XCreateColormap(dpy, root, vi->visual, AllocNone);
  XSetWindowAttributes swa;
  std::memset(&swa, 0, sizeof(swa));
  swa.colormap = impl_->colormap;
  swa.event_mask = ExposureMask | KeyPressMask | StructureNotifyMask;
  swa.override_redirect = config.fullscreen ? True : False;
  swa.background_pixel = 0;
  impl_->window = XCreateWindow(dpy, root, 0, 0, static_cast<unsigned>(width_), static_cast<unsigned>(height_), 0,
                                vi->depth, InputOutput, vi->visual,
                                CWColormap | CWEventMask | CWOverrideRedirect | CWBackPixel, &swa);
  XStoreName(dpy, impl_->window, config.title.c_str());
  impl_->wm_delete = XInternAtom(dpy, "WM_DELETE_WINDOW", False);
  XSetWMProtocols(dpy, impl_->window, &impl_->wm_delete, 1);
  if (config.fullscreen)
  {
    const Atom state = XInternAtom(dpy, "_NET_WM_STATE", False);
    const Atom full = XInternAtom(dpy, "_NET_WM_STATE_FULLSCREEN", False);
    XChangeProperty(dpy, impl_->window, state, XA_ATOM, 32, PropModeReplace,
                    reinterpret_cast<const unsigned char*>(&full), 1);
  }
  XMapRaised(dpy, impl_->window);
  impl_->context = glXCreateContext(dpy, vi, nullptr, True);
  XFree(vi);
  if (!impl_->context || !glXMakeCurrent(dpy, impl_->window, impl_->context))
    throw DisplayError("cannot create or bind a GLX context");
  XSync(dpy, False);

  if (config.vsync)
  {
    using SwapExt = void (*)(Display*, GLXDrawable, int);
    using SwapMesa = int (*)(unsigned);
    const char* exts = glXQueryExtensionsString(dpy, screen);
    if (exts && std::strstr(exts, "GLX_EXT_swap_control"))
    {
      auto f = reinterpret_cast<SwapExt>(glXGetProcAddress(reinterpret_cast<const GLubyte*>("glXSwapIntervalEXT")));
      if (f)
      {
        f(dpy, impl_->window, 1);
        vsync_ = true;
      }
    }
    else if (exts && std::strstr(exts, "GLX_MESA_swap_control"))
    {
      auto f = reinterpret_cast<SwapMesa>(glXGetProcAddress(reinterpret_cast<const GLubyte*>("glXSwapIntervalMESA")));
      if (f && f(1) == 0)
        vsync_ = true;
    }
  }

  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DITHER);
  glDisable(GL_BLEND);
  glDisable(GL_LIGHTING);
  glShadeModel(GL_FLAT);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glDrawBuffer(GL_BACK);
  glReadBuffer(GL_BACK);
}

GlScreenRenderer::~GlScreenRenderer()
{
  if (!impl_ || !impl_->display)
    return;
  glXMakeCurrent(impl_->display, None, nullptr);
  if (impl_->context)
    glXDestroyContext(impl_->display, impl_->context);
  if (impl_->window)
    XDestroyWindow(impl_->display, impl_->window);
  if (impl_->colormap)
    XFreeColormap(impl_->display, impl_->colormap);
  XCloseDisplay(impl_->display);
}

void GlScreenRenderer::clear(double intensity)
{
  const auto v = static_cast<GLclampf>(intensity);
  glClearColor(v, v, v, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
}

void GlScreenRenderer::setMatrices(const Eigen::Matrix4d& projection, const Eigen::Matrix4d& view)
{
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(projection.data());
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(view.data());
}

void GlScreenRenderer::drawScenePolygons(const Scene& scene, double t)
{
  for (size_t k = 0; k < scene.polygons.size(); ++k)
  {
    const double v = scene.polygonIntensity(k, t);
    glColor3d(v, v, v);
    glBegin(GL_POLYGON);
    for (const auto& p : scene.polygons[k].vertices)
      glVertex3d(p.x(), p.y(), 0.0);
    glEnd();
  }
}

void GlScreenRenderer::drawWorldLines(const std::vector<WorldLine>& lines, double width, double intensity)
{
  glColor3d(intensity, intensity, intensity);
  glBegin(GL_QUADS);
  for (const auto& l : lines)
  {
    const Eigen::Vector3d d = l.b - l.a;
    Eigen::Vector3d n = Eigen::Vector3d::UnitZ().cross(d);
    if (n.norm() < 1e-15)
      continue;
    n *= 0.5 * width / n.norm();
    const Eigen::Vector3d q[4] = {l.a - n, l.b - n, l.b + n, l.a + n};
    for (const auto& p : q)
      glVertex3d(p.x(), p.y(), p.z());
  }
  glEnd();
}

void GlScreenRenderer::drawViewportDiscs(const Points2d& centres_vp, double radius_px, double intensity, int segments)
{
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glColor3d(intensity, intensity, intensity);
  const double rx = 2.0 * radius_px / width_, ry = 2.0 * radius_px / height_;
  for (const auto& c : centres_vp)
  {
    glBegin(GL_POLYGON);
    for (int i = 0; i < segments; ++i)
    {
      const double a = 2.0 * M_PI * i / segments;
      glVertex2d(c.x() + rx * std::cos(a), c.y() + ry * std::sin(a));
    }
    glEnd();
  }
}

void GlScreenRenderer::readBackBuffer(std::vector<float>& grey)
{
  rgb_.resize(static_cast<size_t>(width_) * height_ * 3);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, rgb_.data());
  grey.resize(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y)
  {
    const unsigned char* row = &rgb_[static_cast<size_t>(height_ - 1 - y) * width_ * 3];  // GL rows are bottom-up
    float* out = &grey[static_cast<size_t>(y) * width_];
    for (int x = 0; x < width_; ++x)
      out[x] = (0.299f * row[3 * x] + 0.587f * row[3 * x + 1] + 0.114f * row[3 * x + 2]) / 255.0f;
  }
}

void GlScreenRenderer::swap()
{
  glXSwapBuffers(impl_->display, impl_->window);
  glFinish();
}

bool GlScreenRenderer::pollEvents()
{
  bool keep = true;
  while (XPending(impl_->display) > 0)
  {
    XEvent ev;
    XNextEvent(impl_->display, &ev);
    if (ev.type == KeyPress)
      keep = false;
    if (ev.type == ClientMessage && static_cast<Atom>(ev.xclient.data.l[0]) == impl_->wm_delete)
      keep = false;
  }
  return keep;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
