#pragma once

#include <memory>

#include <Eigen/Core>

#include "renders/gl_context.h"
#include "renders/overlay.h"

namespace trav::renders {

/// Where a pass draws: a viewport of the frame [pixels, origin bottom-left] and the camera's
/// OpenGL projection and view matrices (world W to eye).
struct GlCamera {
  int left{0}, bottom{0}, width{1}, height{1};
  Eigen::Matrix4f projection{Eigen::Matrix4f::Identity()};
  Eigen::Matrix4f view_from_W{Eigen::Matrix4f::Identity()};
};

/// A perspective projection as glFrustum(left, right, bottom, top, near, far) makes it.
Eigen::Matrix4f FrustumMatrix(float left, float right, float bottom, float top, float near,
                              float far);

/// The view matrix of a camera at `eye_W` looking along `forward_W` with `up_W` up (gluLookAt).
Eigen::Matrix4f LookAtMatrix(const Eigen::Vector3f& eye_W, const Eigen::Vector3f& forward_W,
                             const Eigen::Vector3f& up_W);

/// What MuJoCo 2.2's renderer cannot draw, drawn into the same frame after it with the same
/// camera: screen-space points (a LiDAR frame as the sensor's rosette, not as cubes) and
/// vertex-coloured translucent meshes (a map draped on the terrain). MuJoCo's scene holds only
/// primitive geoms, each drawn with its own state changes and bounded by the scene's capacity
/// (the earlier videos drew at most 1,200 points as cubes and 3,000 map cells as boxes); here
/// they are one immediate-mode batch each. Written against OpenGL 1.x (the compatibility profile
/// MuJoCo 2.2 itself uses), with entry points looked up in the context's library, so nothing links
/// a GL library.
class GlDraw {
 public:
  /// Looks up the entry points in `context`'s library. @throws std::runtime_error if one lacks.
  explicit GlDraw(const GlContext& context);
  ~GlDraw();
  GlDraw(const GlDraw&) = delete;
  GlDraw& operator=(const GlDraw&) = delete;

  /// Sets the viewport [pixels from the frame's bottom-left] for what MuJoCo draws next in it
  /// (mjr_text draws in relative coordinates of the viewport last set).
  void Viewport(int left, int bottom, int width, int height) const;

  /// Draws `points` as round points of their size in pixels, depth-tested against the scene.
  void Points(const GlCamera& camera, const ColoredPoints& points) const;

  /// Drapes `grid` over its heights: a translucent mesh through the known cells' centres, colours
  /// interpolated between cells, depth-tested but not hiding what lies behind it.
  void Drape(const GlCamera& camera, const GroundGrid& grid) const;

 private:
  struct Functions;
  void Begin(const GlCamera& camera) const;
  void End() const;
  std::unique_ptr<Functions> gl_;
};

}  // namespace trav::renders
