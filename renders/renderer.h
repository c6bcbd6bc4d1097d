#pragma once

#include <memory>
#include <string>

#include "common/archive.h"
#include "renders/camera.h"
#include "renders/gl_context.h"
#include "renders/ground_texture.h"
#include "renders/image.h"
#include "renders/overlay.h"

struct mjrRect_;  // MuJoCo's mjrRect, declared here so that no MuJoCo header leaks out

namespace trav::sim {
class Simulation;
}  // namespace trav::sim

namespace trav::renders {

class GlDraw;

/// Quality and size of rendered frames. The defaults keep a 640 x 480 frame near 20 ms on one CPU
/// core with Mesa's llvmpipe (no shadows, no multisampling): see the README's performance section.
struct RenderConfig {
  int width{640};   ///< of the whole frame, a panel included [pixels], 16..4096
  int height{480};  ///< [pixels], 16..4096
  /// Pixels of the frame's width right of the camera's view, for Overlay::panel; 0: no panel.
  /// Set by the program (the map panel of a closed loop), not a scenario key.
  int panel_width{0};
  /// How the ground is painted (from the terrain type; not a scenario key).
  GroundMaterial ground{GroundMaterial::kGrass};
  GlBackend backend{GlBackend::kOsmesa};
  bool shadows{false};  ///< shadow mapping (about 2x the cost on llvmpipe)
  bool reflections{false};
  int msaa_samples{0};   ///< multisampling, 0 = off
  int max_geoms{30000};  ///< capacity for scene plus overlay geoms

  /// The frame keys of scenario section `video` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("width", &width, {16, 4096});
    a->Field("height", &height, {16, 4096});
    a->Enum("backend", &backend);
    a->Field("shadows", &shadows);
    a->Field("msaa", &msaa_samples, {0, 16});
  }
};

/// Checks the ranges of a render config. @throws common::InputError naming the field and value.
void ValidateRenderConfig(const RenderConfig& config);

/// Off-screen renderer of a Simulation with MuJoCo's renderer: owns the GL context, the MuJoCo
/// scene and the render context. Not thread-safe; one per process (see GlContext).
class Renderer {
 public:
  /// Creates the GL context and uploads the model (sets the simulation model's off-screen size and
  /// quality settings first, as MuJoCo 2.2 reads them when the context is made, and paints the
  /// ground's texture, sim/world_builder.h, from the drawn height field).
  /// @throws std::runtime_error if GL is unavailable.
  Renderer(sim::Simulation* simulation, const RenderConfig& config);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Renders the current state of the simulation seen from `view` into the frame left of the
  /// panel, with `overlay` drawn in the scene and over it, and the overlay's panel (if any) right
  /// of it, into `image` (resized to the configured size; no allocation once it has that size).
  /// @throws std::invalid_argument if the overlay's panel is not panel_width x height.
  void Render(const sim::Simulation& simulation, const CameraView& view, const Overlay& overlay,
              Image* image);

  const RenderConfig& config() const { return config_; }

  /// Height of a line of text in the renderer's normal font, and the width of `text` (one line)
  /// in it [pixels] (for laying out panels).
  int text_height_px() const;
  int TextWidthPx(const std::string& text) const;

 private:
  struct MujocoState;
  // A centred card with `text` over the camera's view `viewport` (TextCorner::kCenter).
  void DrawCard(const std::string& text, const mjrRect_& viewport);
  // The panel's image and texts at column `left` of the frame.
  void DrawPanel(const Panel& panel, int left);
  RenderConfig config_;
  std::unique_ptr<GlContext> gl_;
  std::unique_ptr<GlDraw> draw_;
  std::unique_ptr<MujocoState> mujoco_;
};

}  // namespace trav::renders
