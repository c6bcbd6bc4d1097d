#include "renders/renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <mujoco/mujoco.h>

#include "common/input_error.h"
#include "sim/simulation.h"

namespace trav::renders {
namespace {

// Geom group of the ceiling (world_builder.cc): hidden so the camera can look into rooms.
constexpr int kCeilingGroup = 4;

mjvGeom* NextGeom(mjvScene* scene) {
  if (scene->ngeom >= scene->maxgeom) return nullptr;
  mjvGeom* geom = scene->geoms + scene->ngeom;
  ++scene->ngeom;
  return geom;
}

void InitOverlayGeom(mjvGeom* geom, int type, const mjtNum size[3], const mjtNum pos[3],
                     const float rgba[4]) {
  mjv_initGeom(geom, type, size, pos, nullptr, rgba);
  geom->category = mjCAT_DECOR;
  geom->emission = 0.3f;
}

void DrawPolyline(const Polyline& line, mjvScene* scene) {
  const float rgba[4] = {line.rgba[0], line.rgba[1], line.rgba[2], line.rgba[3]};
  const mjtNum zero[3] = {0, 0, 0};
  for (std::size_t i = 0; i + 1 < line.points_W.size(); ++i) {
    mjvGeom* geom = NextGeom(scene);
    if (geom == nullptr) return;
    const Eigen::Vector3d& a = line.points_W[i];
    const Eigen::Vector3d& b = line.points_W[i + 1];
    InitOverlayGeom(geom, mjGEOM_CAPSULE, zero, zero, rgba);
    mjv_makeConnector(geom, mjGEOM_CAPSULE, 0.5 * line.width_m, a.x(), a.y(), a.z(), b.x(), b.y(),
                      b.z());
  }
}

void DrawPoints(const ColoredPoints& points, mjvScene* scene) {
  const mjtNum size[3] = {points.radius_m, points.radius_m, points.radius_m};
  for (Eigen::Index i = 0; i < points.points_W.cols(); ++i) {
    mjvGeom* geom = NextGeom(scene);
    if (geom == nullptr) return;
    const Eigen::Index c = points.rgba.cols() == 1 ? 0 : i;
    const float rgba[4] = {points.rgba(0, c), points.rgba(1, c), points.rgba(2, c),
                           points.rgba(3, c)};
    const mjtNum pos[3] = {points.points_W(0, i), points.points_W(1, i), points.points_W(2, i)};
    InitOverlayGeom(geom, mjGEOM_BOX, size, pos, rgba);
  }
}

void DrawGrid(const GroundGrid& grid, mjvScene* scene) {
  const common::GridGeometry& g = grid.geometry;
  const long cells = static_cast<long>(g.num_x) * g.num_y;
  const int stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(
                                     static_cast<double>(cells) / std::max(1, grid.max_cells)))));
  const double half = 0.5 * stride * g.resolution_m;
  const mjtNum size[3] = {half, half, 0.01};
  for (int iy = 0; iy < g.num_y; iy += stride) {
    for (int ix = 0; ix < g.num_x; ix += stride) {
      const float value = grid.values(ix, iy);
      if (std::isnan(value) || std::isnan(grid.heights_m(ix, iy))) continue;
      mjvGeom* geom = NextGeom(scene);
      if (geom == nullptr) return;
      const Eigen::Vector3f color = TraversabilityColor(value, grid.value_min, grid.value_max);
      const float rgba[4] = {color.x(), color.y(), color.z(), grid.alpha};
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      const mjtNum pos[3] = {p.x(), p.y(), grid.heights_m(ix, iy) + 0.02};
      InitOverlayGeom(geom, mjGEOM_BOX, size, pos, rgba);
    }
  }
}

int GridPosition(TextCorner corner) {
  switch (corner) {
    case TextCorner::kTopLeft:
      return mjGRID_TOPLEFT;
    case TextCorner::kTopRight:
      return mjGRID_TOPRIGHT;
    case TextCorner::kBottomLeft:
      return mjGRID_BOTTOMLEFT;
    case TextCorner::kBottomRight:
      return mjGRID_BOTTOMRIGHT;
  }
  return mjGRID_TOPLEFT;
}

}  // namespace

Eigen::Vector3f TraversabilityColor(float value, float low, float high) {
  const float t = high > low ? std::clamp((value - low) / (high - low), 0.0f, 1.0f) : 0.0f;
  // green (0.1, 0.75, 0.2) -> yellow (0.95, 0.85, 0.1) -> red (0.85, 0.1, 0.1)
  if (t < 0.5f) {
    const float s = 2.0f * t;
    return {0.1f + 0.85f * s, 0.75f + 0.1f * s, 0.2f - 0.1f * s};
  }
  const float s = 2.0f * (t - 0.5f);
  return {0.95f - 0.1f * s, 0.85f - 0.75f * s, 0.1f};
}

void ValidateRenderConfig(const RenderConfig& config) {
  auto check = [](bool ok, const char* field, int value, const char* what) {
    if (!ok) {
      throw common::InputError("", field, "value " + std::to_string(value) + " " + what);
    }
  };
  check(config.width >= 16 && config.width <= 4096, "width", config.width, "must be in [16, 4096]");
  check(config.height >= 16 && config.height <= 4096, "height", config.height,
        "must be in [16, 4096]");
  check(config.msaa_samples >= 0 && config.msaa_samples <= 16, "msaa", config.msaa_samples,
        "must be in [0, 16]");
}

struct Renderer::MujocoState {
  mjvScene scene;
  mjrContext context;
  mjvOption option;
  mjvCamera camera;
  std::vector<unsigned char> rgb_bottom_up;
};

Renderer::Renderer(sim::Simulation* simulation, const RenderConfig& config) : config_(config) {
  ValidateRenderConfig(config_);
  gl_ = GlContext::Create(config_.backend, config_.width, config_.height);

  // MuJoCo 2.2 sizes the off-screen buffer from the model when the context is made
  mjModel* model = simulation->mutable_model();
  model->vis.global.offwidth = config_.width;
  model->vis.global.offheight = config_.height;
  model->vis.quality.offsamples = config_.msaa_samples;
  model->vis.quality.shadowsize = config_.shadows ? 2048 : 1024;

  mujoco_ = std::make_unique<MujocoState>();
  mjv_defaultScene(&mujoco_->scene);
  mjr_defaultContext(&mujoco_->context);
  mjv_defaultOption(&mujoco_->option);
  mjv_defaultCamera(&mujoco_->camera);
  mujoco_->option.geomgroup[kCeilingGroup] = 0;
  mujoco_->camera.type = mjCAMERA_FREE;
  mjv_makeScene(model, &mujoco_->scene, config_.max_geoms);
  mjr_makeContext(model, &mujoco_->context, mjFONTSCALE_150);
  mjr_setBuffer(mjFB_OFFSCREEN, &mujoco_->context);
  if (mujoco_->context.currentBuffer != mjFB_OFFSCREEN) {
    mjr_freeContext(&mujoco_->context);
    mjv_freeScene(&mujoco_->scene);
    throw std::runtime_error("MuJoCo: the off-screen buffer is not supported by this GL context");
  }
  mujoco_->scene.flags[mjRND_SHADOW] = config_.shadows ? 1 : 0;
  mujoco_->scene.flags[mjRND_REFLECTION] = config_.reflections ? 1 : 0;
  mujoco_->rgb_bottom_up.resize(static_cast<std::size_t>(config_.width) * config_.height * 3);
}

Renderer::~Renderer() {
  mjr_freeContext(&mujoco_->context);
  mjv_freeScene(&mujoco_->scene);
}

void Renderer::Render(const sim::Simulation& simulation, const CameraView& view,
                      const Overlay& overlay, Image* image) {
  MujocoState& mj = *mujoco_;
  mj.camera.lookat[0] = view.lookat_W.x();
  mj.camera.lookat[1] = view.lookat_W.y();
  mj.camera.lookat[2] = view.lookat_W.z();
  mj.camera.distance = view.distance_m;
  mj.camera.azimuth = view.azimuth_deg;
  mj.camera.elevation = view.elevation_deg;

  // mjv_updateScene only reads mjData; its signature takes it non-const
  mjv_updateScene(simulation.model(), const_cast<mjData*>(simulation.data()), &mj.option, nullptr,
                  &mj.camera, mjCAT_ALL, &mj.scene);
  for (const GroundGrid& grid : overlay.grids) DrawGrid(grid, &mj.scene);
  for (const Polyline& line : overlay.polylines) DrawPolyline(line, &mj.scene);
  for (const ColoredPoints& points : overlay.points) DrawPoints(points, &mj.scene);

  const mjrRect viewport = {0, 0, config_.width, config_.height};
  mjr_render(viewport, &mj.scene, &mj.context);
  for (const TextLabel& label : overlay.texts) {
    mjr_overlay(mjFONT_NORMAL, GridPosition(label.corner), viewport, label.text.c_str(), nullptr,
                &mj.context);
  }
  mjr_readPixels(mj.rgb_bottom_up.data(), nullptr, viewport, &mj.context);

  // OpenGL rows are bottom-up; images are top-down
  image->width = config_.width;
  image->height = config_.height;
  const std::size_t row_bytes = static_cast<std::size_t>(config_.width) * 3;
  image->rgb.resize(row_bytes * config_.height);
  for (int y = 0; y < config_.height; ++y) {
    std::copy_n(mj.rgb_bottom_up.data() + row_bytes * (config_.height - 1 - y), row_bytes,
                image->rgb.data() + row_bytes * y);
  }
}

}  // namespace trav::renders
