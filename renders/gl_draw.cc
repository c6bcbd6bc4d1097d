#include "renders/gl_draw.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace trav::renders {
namespace {

// OpenGL 1.x enumerants (GL/gl.h; not included, so that no GL header leaks into this module)
constexpr unsigned kProjection = 0x1701;         // GL_PROJECTION
constexpr unsigned kModelview = 0x1700;          // GL_MODELVIEW
constexpr unsigned kAllAttribBits = 0x000fffff;  // GL_ALL_ATTRIB_BITS
constexpr unsigned kLighting = 0x0B50;           // GL_LIGHTING
constexpr unsigned kTexture2d = 0x0DE1;          // GL_TEXTURE_2D
constexpr unsigned kCullFace = 0x0B44;           // GL_CULL_FACE
constexpr unsigned kDepthTest = 0x0B71;          // GL_DEPTH_TEST
constexpr unsigned kBlend = 0x0BE2;              // GL_BLEND
constexpr unsigned kPointSmooth = 0x0B10;        // GL_POINT_SMOOTH
constexpr unsigned kPolygonOffsetFill = 0x8037;  // GL_POLYGON_OFFSET_FILL
constexpr unsigned kSrcAlpha = 0x0302;           // GL_SRC_ALPHA
constexpr unsigned kOneMinusSrcAlpha = 0x0303;   // GL_ONE_MINUS_SRC_ALPHA
constexpr unsigned kLequal = 0x0203;             // GL_LEQUAL
constexpr unsigned kPoints = 0x0000;             // GL_POINTS
constexpr unsigned kTriangles = 0x0004;          // GL_TRIANGLES
constexpr unsigned kSmooth = 0x1D01;             // GL_SMOOTH
constexpr unsigned char kFalse = 0, kTrue = 1;

}  // namespace

struct GlDraw::Functions {
  void (*Viewport)(int, int, int, int);
  void (*MatrixMode)(unsigned);
  void (*LoadMatrixf)(const float*);
  void (*PushMatrix)();
  void (*PopMatrix)();
  void (*PushAttrib)(unsigned);
  void (*PopAttrib)();
  void (*Enable)(unsigned);
  void (*Disable)(unsigned);
  void (*BlendFunc)(unsigned, unsigned);
  void (*DepthFunc)(unsigned);
  void (*DepthMask)(unsigned char);
  void (*PointSize)(float);
  void (*PolygonOffset)(float, float);
  void (*ShadeModel)(unsigned);
  void (*Begin)(unsigned);
  void (*End)();
  void (*Color4f)(float, float, float, float);
  void (*Vertex3f)(float, float, float);
};

namespace {

template <typename Function>
void Load(const GlContext& context, const char* name, Function* function) {
  *function = reinterpret_cast<Function>(context.ProcAddress(name));
  if (*function == nullptr) {
    throw std::runtime_error(std::string("the GL library lacks ") + name);
  }
}

}  // namespace

Eigen::Matrix4f FrustumMatrix(float left, float right, float bottom, float top, float near,
                              float far) {
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = 2.0f * near / (right - left);
  m(0, 2) = (right + left) / (right - left);
  m(1, 1) = 2.0f * near / (top - bottom);
  m(1, 2) = (top + bottom) / (top - bottom);
  m(2, 2) = -(far + near) / (far - near);
  m(2, 3) = -2.0f * far * near / (far - near);
  m(3, 2) = -1.0f;
  return m;
}

Eigen::Matrix4f LookAtMatrix(const Eigen::Vector3f& eye_W, const Eigen::Vector3f& forward_W,
                             const Eigen::Vector3f& up_W) {
  const Eigen::Vector3f f = forward_W.normalized();
  const Eigen::Vector3f s = f.cross(up_W).normalized();
  const Eigen::Vector3f u = s.cross(f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye_W);
  m(1, 3) = -u.dot(eye_W);
  m(2, 3) = f.dot(eye_W);
  return m;
}

GlDraw::GlDraw(const GlContext& context) : gl_(std::make_unique<Functions>()) {
  Functions& f = *gl_;
  Load(context, "glViewport", &f.Viewport);
  Load(context, "glMatrixMode", &f.MatrixMode);
  Load(context, "glLoadMatrixf", &f.LoadMatrixf);
  Load(context, "glPushMatrix", &f.PushMatrix);
  Load(context, "glPopMatrix", &f.PopMatrix);
  Load(context, "glPushAttrib", &f.PushAttrib);
  Load(context, "glPopAttrib", &f.PopAttrib);
  Load(context, "glEnable", &f.Enable);
  Load(context, "glDisable", &f.Disable);
  Load(context, "glBlendFunc", &f.BlendFunc);
  Load(context, "glDepthFunc", &f.DepthFunc);
  Load(context, "glDepthMask", &f.DepthMask);
  Load(context, "glPointSize", &f.PointSize);
  Load(context, "glPolygonOffset", &f.PolygonOffset);
  Load(context, "glShadeModel", &f.ShadeModel);
  Load(context, "glBegin", &f.Begin);
  Load(context, "glEnd", &f.End);
  Load(context, "glColor4f", &f.Color4f);
  Load(context, "glVertex3f", &f.Vertex3f);
}

GlDraw::~GlDraw() = default;

void GlDraw::Viewport(int left, int bottom, int width, int height) const {
  gl_->Viewport(left, bottom, width, height);
}

void GlDraw::Begin(const GlCamera& camera) const {
  const Functions& f = *gl_;
  f.PushAttrib(kAllAttribBits);
  f.Viewport(camera.left, camera.bottom, camera.width, camera.height);
  f.MatrixMode(kProjection);
  f.PushMatrix();
  f.LoadMatrixf(camera.projection.data());  // Eigen's default storage is column-major, as GL's
  f.MatrixMode(kModelview);
  f.PushMatrix();
  f.LoadMatrixf(camera.view_from_W.data());
  f.Disable(kLighting);
  f.Disable(kTexture2d);
  f.Disable(kCullFace);
  f.Enable(kDepthTest);
  f.DepthFunc(kLequal);
  f.Enable(kBlend);
  f.BlendFunc(kSrcAlpha, kOneMinusSrcAlpha);
  f.ShadeModel(kSmooth);
}

void GlDraw::End() const {
  const Functions& f = *gl_;
  f.MatrixMode(kModelview);
  f.PopMatrix();
  f.MatrixMode(kProjection);
  f.PopMatrix();
  f.MatrixMode(kModelview);
  f.PopAttrib();
}

void GlDraw::Points(const GlCamera& camera, const ColoredPoints& points) const {
  if (points.points_W.cols() == 0 || points.rgba.cols() == 0) return;
  const Functions& f = *gl_;
  Begin(camera);
  f.Enable(kPointSmooth);
  f.PointSize(points.size_px);
  f.Begin(kPoints);
  const bool one_colour = points.rgba.cols() == 1;
  for (Eigen::Index i = 0; i < points.points_W.cols(); ++i) {
    const auto c = points.rgba.col(one_colour ? 0 : i);
    f.Color4f(c[0], c[1], c[2], c[3]);
    f.Vertex3f(points.points_W(0, i), points.points_W(1, i), points.points_W(2, i));
  }
  f.End();
  End();
}

void GlDraw::Drape(const GlCamera& camera, const GroundGrid& grid) const {
  const common::GridGeometry& g = grid.geometry;
  if (g.num_x < 1 || g.num_y < 1) return;
  // corners of the cells: height and value the mean of the known cells around each corner
  const int nx = g.num_x + 1, ny = g.num_y + 1;
  Eigen::MatrixXf corner_height = Eigen::MatrixXf::Zero(nx, ny);
  Eigen::MatrixXf corner_value = Eigen::MatrixXf::Zero(nx, ny);
  Eigen::MatrixXi corner_count = Eigen::MatrixXi::Zero(nx, ny);
  auto known = [&](int ix, int iy) {
    return !std::isnan(grid.values(ix, iy)) && !std::isnan(grid.heights_m(ix, iy));
  };
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      if (!known(ix, iy)) continue;
      for (int c = 0; c < 4; ++c) {
        const int cx = ix + (c & 1), cy = iy + (c >> 1);
        corner_height(cx, cy) += grid.heights_m(ix, iy);
        corner_value(cx, cy) += grid.values(ix, iy);
        ++corner_count(cx, cy);
      }
    }
  }
  const Functions& f = *gl_;
  Begin(camera);
  f.DepthMask(kFalse);  // translucent: what lies behind stays visible
  f.Enable(kPolygonOffsetFill);
  f.PolygonOffset(-1.0f, -4.0f);
  const Eigen::Vector2d origin =
      g.CellCenter(0, 0) - Eigen::Vector2d::Constant(0.5 * g.resolution_m);
  auto vertex = [&](int cx, int cy) {
    const float n = static_cast<float>(corner_count(cx, cy));
    const Eigen::Vector3f colour =
        TraversabilityColor(corner_value(cx, cy) / n, grid.value_min, grid.value_max);
    f.Color4f(colour.x(), colour.y(), colour.z(), grid.alpha);
    f.Vertex3f(static_cast<float>(origin.x() + cx * g.resolution_m),
               static_cast<float>(origin.y() + cy * g.resolution_m),
               static_cast<float>(corner_height(cx, cy) / n + grid.lift_m));
  };
  f.Begin(kTriangles);
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      if (!known(ix, iy)) continue;
      vertex(ix, iy);
      vertex(ix + 1, iy);
      vertex(ix + 1, iy + 1);
      vertex(ix, iy);
      vertex(ix + 1, iy + 1);
      vertex(ix, iy + 1);
    }
  }
  f.End();
  f.DepthMask(kTrue);
  End();
}

}  // namespace trav::renders
