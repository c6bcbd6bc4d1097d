#pragma once

#include <array>
#include <memory>
#include <string>

#include "common/enum_names.h"

namespace trav::renders {

/// Off-screen OpenGL platform.
enum class GlBackend {
  kOsmesa,  ///< Mesa's software off-screen library (libOSMesa): works everywhere, CPU only
  kEgl,     ///< EGL; headless through Mesa's surfaceless platform, or a GPU driver where present
};

/// The names of GlBackend's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<GlBackend>, 2> kGlBackendNames{
    {{GlBackend::kOsmesa, "osmesa"}, {GlBackend::kEgl, "egl"}}};
constexpr const auto& EnumNames(GlBackend) { return kGlBackendNames; }

/// A current off-screen OpenGL context. The platform library is loaded at run time (dlopen), so a
/// process that never renders needs no GL library at all. MuJoCo's GL loader picks the first
/// platform it finds in the process, so a process uses one backend only.
class GlContext {
 public:
  /// Creates a context of at least `width` x `height` pixels and makes it current.
  /// @throws std::runtime_error if the platform library is missing or the context cannot be made,
  /// or if another backend was already loaded in this process.
  static std::unique_ptr<GlContext> Create(GlBackend backend, int width, int height);

  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  /// The backend of this context.
  virtual GlBackend backend() const = 0;

  /// The address of the OpenGL function `name` of this context's library (core and legacy entry
  /// points alike), or nullptr if it has none.
  virtual void* ProcAddress(const char* name) const = 0;

 protected:
  GlContext() = default;
};

}  // namespace trav::renders
