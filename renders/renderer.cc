#include "renders/renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <mujoco/mujoco.h>

#include "common/input_error.h"
#include "renders/gl_draw.h"
#include "sim/simulation.h"
#include "sim/world_builder.h"

namespace trav::renders {
namespace {

// Geom groups (world_builder.cc): the ceiling, hidden so the camera can look into rooms; tree
// crowns, hidden on request.
constexpr int kCanopyGroup = 2;
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

// A capsule from a to b (in W) of radius `radius_m`.
void AddCapsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_m,
                const Eigen::Vector4f& rgba, mjvScene* scene) {
  mjvGeom* geom = NextGeom(scene);
  if (geom == nullptr) return;
  const float colour[4] = {rgba[0], rgba[1], rgba[2], rgba[3]};
  const mjtNum zero[3] = {0, 0, 0};
  InitOverlayGeom(geom, mjGEOM_CAPSULE, zero, zero, colour);
  geom->emission = 0.0f;
  mjv_makeConnector(geom, mjGEOM_CAPSULE, radius_m, a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
}

// A geom of `type` with half-sizes `size` at pose X_WG.
void AddSolid(int type, const Eigen::Vector3d& size, const Eigen::Isometry3d& X_WG,
              const Eigen::Vector4f& rgba, mjvScene* scene) {
  mjvGeom* geom = NextGeom(scene);
  if (geom == nullptr) return;
  const float colour[4] = {rgba[0], rgba[1], rgba[2], rgba[3]};
  const mjtNum half[3] = {size.x(), size.y(), size.z()};
  const mjtNum pos[3] = {X_WG.translation().x(), X_WG.translation().y(), X_WG.translation().z()};
  mjtNum mat[9];
  Eigen::Map<Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>> rotation(mat);
  rotation = X_WG.linear();
  mjv_initGeom(geom, type, half, pos, mat, colour);
  geom->category = mjCAT_DECOR;
}

// Proportions of the walking figure, as fractions of its height, and its swing [rad].
constexpr double kLegLength = 0.47, kShoulderHeight = 0.82, kHeadHeight = 0.93;
constexpr double kHipHalfWidth = 0.055, kShoulderHalfWidth = 0.12, kArmLength = 0.36;
constexpr double kLegSwingRad = 0.45, kArmSwingRad = 0.35;

void DrawWalker(const Walker& walker, mjvScene* scene) {
  const double h = walker.height_m;
  const Eigen::Isometry3d& X = walker.X_WO;
  auto at = [&](double x, double y, double z_above_feet) -> Eigen::Vector3d {
    return X * Eigen::Vector3d(x, y, z_above_feet - 0.5 * h);
  };
  const Eigen::Vector4f trousers(0.2f, 0.22f, 0.3f, 1.0f), skin(0.85f, 0.68f, 0.55f, 1.0f);
  const double swing = std::sin(walker.gait_phase_rad);
  const double hip_z = kLegLength * h, leg = (kLegLength - 0.03) * h;
  const double shoulder_z = kShoulderHeight * h, arm = kArmLength * h;
  for (int side = -1; side <= 1; side += 2) {  // side +1: the left (+y) limbs
    const double leg_angle = side * kLegSwingRad * swing;
    AddCapsule(
        at(0, side * kHipHalfWidth * h, hip_z),
        at(leg * std::sin(leg_angle), side * kHipHalfWidth * h, hip_z - leg * std::cos(leg_angle)),
        0.045 * h, trousers, scene);
    const double arm_angle = -side * kArmSwingRad * swing;
    AddCapsule(at(0, side * kShoulderHalfWidth * h, shoulder_z),
               at(arm * std::sin(arm_angle), side * (kShoulderHalfWidth + 0.02) * h,
                  shoulder_z - arm * std::cos(arm_angle)),
               0.03 * h, walker.rgba, scene);
  }
  AddCapsule(at(0, 0, hip_z + 0.04 * h), at(0, 0, shoulder_z - 0.02 * h), 0.1 * h, walker.rgba,
             scene);
  AddSolid(mjGEOM_SPHERE, Eigen::Vector3d::Constant(0.065 * h),
           Eigen::Isometry3d(Eigen::Translation3d(at(0, 0, kHeadHeight * h))), skin, scene);
}

void DrawCart(const Cart& cart, mjvScene* scene) {
  const Eigen::Vector3d& half = cart.half_extents_m;
  const double wheel_r = std::max(0.04, 0.2 * half.z());
  const Eigen::Isometry3d& X = cart.X_WO;
  // the basket: from above the wheels to the top of the bounding box
  const double bottom = -half.z() + 1.6 * wheel_r;
  Eigen::Isometry3d X_basket = X;
  X_basket.translate(Eigen::Vector3d(0, 0, 0.5 * (bottom + half.z())));
  AddSolid(mjGEOM_BOX, Eigen::Vector3d(0.85 * half.x(), half.y(), 0.5 * (half.z() - bottom)),
           X_basket, cart.rgba, scene);
  const Eigen::Vector4f rubber(0.08f, 0.08f, 0.08f, 1.0f), metal(0.7f, 0.7f, 0.72f, 1.0f);
  for (int i = 0; i < 4; ++i) {
    const double x = ((i & 1) != 0 ? 0.7 : -0.7) * half.x();
    const double y = ((i & 2) != 0 ? 0.85 : -0.85) * half.y();
    Eigen::Isometry3d X_wheel = X;
    X_wheel.translate(Eigen::Vector3d(x, y, -half.z() + wheel_r));
    X_wheel.rotate(Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitX()));
    AddSolid(mjGEOM_CYLINDER, Eigen::Vector3d(wheel_r, wheel_r, 0.02), X_wheel, rubber, scene);
  }
  // the push handle: two uprights behind the basket and a bar across
  const double handle_x = -0.85 * half.x() - 0.08;
  for (int side = -1; side <= 1; side += 2) {
    AddCapsule(X * Eigen::Vector3d(-0.85 * half.x(), side * 0.8 * half.y(), bottom),
               X * Eigen::Vector3d(handle_x, side * 0.8 * half.y(), half.z()), 0.012, metal, scene);
  }
  AddCapsule(X * Eigen::Vector3d(handle_x, -0.8 * half.y(), half.z()),
             X * Eigen::Vector3d(handle_x, 0.8 * half.y(), half.z()), 0.018, metal, scene);
}

// Copies `rows` rows of `width` RGB pixels from `source` to `destination` in reverse row order
// (images are stored top-down, OpenGL and MuJoCo's textures bottom-up).
void CopyRowsFlipped(const std::uint8_t* source, int width, int rows, std::uint8_t* destination) {
  const std::size_t row_bytes = 3 * static_cast<std::size_t>(width);
  for (int r = 0; r < rows; ++r) {
    std::copy_n(source + row_bytes * r, row_bytes, destination + row_bytes * (rows - 1 - r));
  }
}

// Removes from `scene` the geoms of the bodies in `bodies`.
void HideBodies(const mjModel* model, const std::vector<int>& bodies, mjvScene* scene) {
  if (bodies.empty()) return;
  int kept = 0;
  for (int i = 0; i < scene->ngeom; ++i) {
    const mjvGeom& geom = scene->geoms[i];
    const bool hidden =
        geom.objtype == mjOBJ_GEOM &&
        std::find(bodies.begin(), bodies.end(), model->geom_bodyid[geom.objid]) != bodies.end();
    if (!hidden) scene->geoms[kept++] = geom;
  }
  scene->ngeom = kept;
}

// Paints the ground's texture of `model` (sim/world_builder.h) from its drawn height field.
void PaintGround(mjModel* model, GroundMaterial material) {
  const int texture = mj_name2id(model, mjOBJ_TEXTURE, sim::kGroundTextureName);
  const int hfield = mj_name2id(model, mjOBJ_HFIELD, "terrain_visual");
  if (texture < 0 || hfield < 0 || model->tex_width[texture] != model->tex_height[texture]) return;
  const int nrow = model->hfield_nrow[hfield], ncol = model->hfield_ncol[hfield];
  if (nrow < 2 || ncol < 2) return;
  const float* samples = model->hfield_data + model->hfield_adr[hfield];
  const mjtNum* size = model->hfield_size + 4 * hfield;
  Eigen::MatrixXf height_m(ncol, nrow);
  for (int r = 0; r < nrow; ++r) {
    for (int c = 0; c < ncol; ++c) {
      height_m(c, r) = static_cast<float>(samples[r * ncol + c] * size[2]);
    }
  }
  const std::vector<std::uint8_t> rgb = GroundTexture(
      height_m, Eigen::Vector2d(2.0 * size[0], 2.0 * size[1]), material, model->tex_width[texture]);
  // MuJoCo maps a 2D texture's first row to the far (+y) edge of a height field
  CopyRowsFlipped(rgb.data(), model->tex_width[texture], model->tex_height[texture],
                  model->tex_rgb + model->tex_adr[texture]);
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
    case TextCorner::kCenter:
      break;  // drawn as a card, not by mjr_overlay
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
  check(config.panel_width >= 0 && config.panel_width <= config.width - 16, "panel_width",
        config.panel_width, "must leave the camera's view at least 16 pixels");
}

struct Renderer::MujocoState {
  mjModel* model;
  mjvScene scene;
  mjrContext context;
  mjvOption option;
  mjvCamera camera;
  std::vector<unsigned char> rgb_bottom_up;
  std::vector<unsigned char> panel_bottom_up;
  std::vector<int> hidden_bodies;
};

Renderer::Renderer(sim::Simulation* simulation, const RenderConfig& config) : config_(config) {
  ValidateRenderConfig(config_);
  gl_ = GlContext::Create(config_.backend, config_.width, config_.height);
  draw_ = std::make_unique<GlDraw>(*gl_);

  // MuJoCo 2.2 sizes the off-screen buffer from the model when the context is made
  mjModel* model = simulation->mutable_model();
  model->vis.global.offwidth = config_.width;
  model->vis.global.offheight = config_.height;
  model->vis.quality.offsamples = config_.msaa_samples;
  model->vis.quality.shadowsize = config_.shadows ? 2048 : 1024;
  PaintGround(model, config_.ground);

  mujoco_ = std::make_unique<MujocoState>();
  mujoco_->model = model;
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

namespace {

// The GL camera MuJoCo 2.2's mjr_render draws `scene` with in `viewport` (its glFrustum and
// lookAt; the scene's own transform is the identity).
GlCamera CameraOf(const mjvScene& scene, const mjrRect& viewport) {
  const mjvGLCamera& c = scene.camera[0];
  const float half_width = 0.5f * static_cast<float>(viewport.width) / viewport.height *
                           (c.frustum_top - c.frustum_bottom);
  GlCamera camera;
  camera.left = viewport.left;
  camera.bottom = viewport.bottom;
  camera.width = viewport.width;
  camera.height = viewport.height;
  camera.projection = FrustumMatrix(c.frustum_center - half_width, c.frustum_center + half_width,
                                    c.frustum_bottom, c.frustum_top, c.frustum_near, c.frustum_far);
  camera.view_from_W = LookAtMatrix(Eigen::Vector3f(c.pos[0], c.pos[1], c.pos[2]),
                                    Eigen::Vector3f(c.forward[0], c.forward[1], c.forward[2]),
                                    Eigen::Vector3f(c.up[0], c.up[1], c.up[2]));
  return camera;
}

// Width [pixels] of the widest line of `text` in `font`.
int TextWidth(const std::string& text, int font, const mjrContext& context) {
  const int* widths = font == mjFONT_BIG ? context.charWidthBig : context.charWidth;
  int widest = 0, line = 0;
  for (const char ch : text) {
    if (ch == '\n') {
      line = 0;
      continue;
    }
    const auto index = static_cast<unsigned char>(ch);
    line += index < 127 ? widths[index] : 0;
    widest = std::max(widest, line);
  }
  return widest;
}

// Draws `text` line by line with its top-left corner at (x, y) [pixels from the viewport's
// bottom-left], in the viewport last set.
void DrawTextAt(const std::string& text, int font, int x, int y, const Eigen::Vector3f& rgb,
                const mjrRect& viewport, const mjrContext& context) {
  const int line_height = font == mjFONT_BIG ? context.charHeightBig : context.charHeight;
  std::size_t begin = 0;
  for (int line = 0; begin <= text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    const std::string part = text.substr(begin, end - begin);
    // mjr_text places the baseline of the text at relative coordinates of the viewport
    const float baseline = static_cast<float>(y - (line + 1) * line_height + line_height / 4);
    mjr_text(font, part.c_str(), &context, static_cast<float>(x) / viewport.width,
             baseline / viewport.height, rgb.x(), rgb.y(), rgb.z());
    begin = end + 1;
  }
}

}  // namespace

int Renderer::text_height_px() const { return mujoco_->context.charHeight; }

int Renderer::TextWidthPx(const std::string& text) const {
  return TextWidth(text, mjFONT_NORMAL, mujoco_->context);
}

void Renderer::Render(const sim::Simulation& simulation, const CameraView& view,
                      const Overlay& overlay, Image* image) {
  MujocoState& mj = *mujoco_;
  const int view_width = config_.width - config_.panel_width;
  if (!overlay.panel.image.rgb.empty() && (overlay.panel.image.width != config_.panel_width ||
                                           overlay.panel.image.height != config_.height)) {
    throw std::invalid_argument("Renderer: the panel must be panel_width x height pixels");
  }
  mj.camera.lookat[0] = view.lookat_W.x();
  mj.camera.lookat[1] = view.lookat_W.y();
  mj.camera.lookat[2] = view.lookat_W.z();
  mj.camera.distance = view.distance_m;
  mj.camera.azimuth = view.azimuth_deg;
  mj.camera.elevation = view.elevation_deg;
  mj.model->vis.global.fovy = static_cast<float>(view.fovy_deg);
  mj.option.geomgroup[kCanopyGroup] = view.hide_canopy ? 0 : 1;

  // mjv_updateScene only reads mjData; its signature takes it non-const
  mjv_updateScene(simulation.model(), const_cast<mjData*>(simulation.data()), &mj.option, nullptr,
                  &mj.camera, mjCAT_ALL, &mj.scene);
  mj.hidden_bodies.clear();
  for (const int mover : overlay.hidden_movers) {
    mj.hidden_bodies.push_back(simulation.MoverBodyId(mover));
  }
  HideBodies(simulation.model(), mj.hidden_bodies, &mj.scene);
  for (const Walker& walker : overlay.walkers) DrawWalker(walker, &mj.scene);
  for (const Cart& cart : overlay.carts) DrawCart(cart, &mj.scene);
  for (const Polyline& line : overlay.polylines) DrawPolyline(line, &mj.scene);

  const mjrRect viewport = {0, 0, view_width, config_.height};
  mjr_render(viewport, &mj.scene, &mj.context);
  const GlCamera camera = CameraOf(mj.scene, viewport);
  for (const GroundGrid& grid : overlay.grids) draw_->Drape(camera, grid);
  for (const ColoredPoints& points : overlay.points) draw_->Points(camera, points);
  for (const TextLabel& label : overlay.texts) {
    if (label.corner != TextCorner::kCenter) {
      mjr_overlay(mjFONT_NORMAL, GridPosition(label.corner), viewport, label.text.c_str(), nullptr,
                  &mj.context);
      continue;
    }
    DrawCard(label.text, viewport);
  }

  if (!overlay.panel.image.rgb.empty()) DrawPanel(overlay.panel, view_width);

  const mjrRect frame = {0, 0, config_.width, config_.height};
  mjr_readPixels(mj.rgb_bottom_up.data(), nullptr, frame, &mj.context);
  image->width = config_.width;
  image->height = config_.height;
  image->rgb.resize(mj.rgb_bottom_up.size());
  CopyRowsFlipped(mj.rgb_bottom_up.data(), config_.width, config_.height, image->rgb.data());
}

void Renderer::DrawCard(const std::string& text, const mjrRect& viewport) {
  const mjrContext& context = mujoco_->context;
  // the text on a dark translucent rectangle in the middle, in the big font if it fits
  const int lines = 1 + static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  const int font =
      TextWidth(text, mjFONT_BIG, context) < 0.8 * viewport.width ? mjFONT_BIG : mjFONT_NORMAL;
  const int line_height = font == mjFONT_BIG ? context.charHeightBig : context.charHeight;
  const int width = std::min(viewport.width, TextWidth(text, font, context) + 2 * line_height);
  const int height = std::min(viewport.height, (lines + 1) * line_height);
  const mjrRect card = {(viewport.width - width) / 2, (viewport.height - height) / 2, width,
                        height};
  mjr_rectangle(card, 0.05f, 0.05f, 0.08f, 0.8f);
  draw_->Viewport(viewport.left, viewport.bottom, viewport.width, viewport.height);
  DrawTextAt(text, font, card.left + line_height, card.bottom + height - line_height / 2,
             Eigen::Vector3f::Ones(), viewport, context);
}

void Renderer::DrawPanel(const Panel& panel, int left) {
  MujocoState& mj = *mujoco_;
  const Image& image = panel.image;
  mj.panel_bottom_up.resize(image.rgb.size());
  CopyRowsFlipped(image.rgb.data(), image.width, image.height, mj.panel_bottom_up.data());
  const mjrRect viewport = {left, 0, image.width, image.height};
  mjr_drawPixels(mj.panel_bottom_up.data(), nullptr, viewport, &mj.context);
  draw_->Viewport(viewport.left, viewport.bottom, viewport.width, viewport.height);
  for (const PanelText& text : panel.texts) {
    DrawTextAt(text.text, mjFONT_NORMAL, text.top_left_px.x(), image.height - text.top_left_px.y(),
               text.rgb, viewport, mj.context);
  }
}

}  // namespace trav::renders
