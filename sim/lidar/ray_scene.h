#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/mesh.h"

namespace trav::lidar {

/// The diffuse reflectance of an object whose description gives none.
inline constexpr float kDefaultReflectance = 0.3f;

/// Plain description of what rays can hit, in the world frame W. Object ids are assigned in this
/// order: `meshes_W`, then `primitives_W`, then `moving_meshes_I`.
struct RaySceneDescription {
  std::vector<common::TriangleMesh> meshes_W;  ///< static meshes (the terrain at full resolution)
  /// Static obstacle primitives: spheres hit on their exact surface, boxes as their 12 triangles,
  /// cylinders and capsules as triangles (`primitive_segments`).
  std::vector<common::Primitive> primitives_W;
  /// Moving objects: each a mesh in its own frame I, placed by `X_WI` (updatable between casts).
  std::vector<common::TriangleMesh> moving_meshes_I;
  std::vector<Eigen::Isometry3d> X_WI;
  /// Diffuse reflectance in [0, 1] of each object at the LiDAR's wavelength, in object-id order;
  /// empty: every object kDefaultReflectance. Otherwise one entry per object.
  std::vector<float> reflectance;
  /// Cylinders and capsules are tessellated with this many segments around (a cylinder of radius r
  /// deviates at most r (1 - cos(pi / segments)) from its polygon: 0.2 % of r at 48).
  int primitive_segments{48};
};

/// Results of a batch of rays, one entry per ray. Misses have range +inf, object id -1 and a zero
/// normal.
struct RayHits {
  Eigen::VectorXf range_m;    ///< distance along the (unit) ray direction [m]
  Eigen::VectorXi object_id;  ///< index of the object hit (see RaySceneDescription)
  Eigen::Matrix3Xf normal_W;  ///< unit surface normal at the hit, in W

  /// Number of entries (at least the number of rays of the last cast).
  Eigen::Index size() const { return range_m.size(); }
};

/// An Embree 3 scene for casting rays against the simulated world. Static geometry is built once
/// (BVH of medium build quality); moving objects are instances whose poses can be updated between
/// casts. Casting is const and thread-safe; results do not depend on the number of threads.
/// The version of the Embree library the ray scene is built with ("3.13.5").
std::string EmbreeVersion();

class RayScene {
 public:
  /// Builds the scene. @throws std::runtime_error on an Embree error (out of memory, bad geometry).
  explicit RayScene(const RaySceneDescription& description);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  /// Number of objects (meshes, primitives and moving meshes).
  int num_objects() const { return num_objects_; }

  /// Diffuse reflectance of object `object_id` (RaySceneDescription::reflectance), in [0, 1].
  float reflectance(int object_id) const {
    return reflectance_[static_cast<std::size_t>(object_id)];
  }

  /// Number of moving objects (meshes posed by SetMovingPose).
  int num_moving() const;

  /// Moves the moving object `index` (0-based among the moving meshes) to X_WI (nothing to do when
  /// it is there already). @throws std::out_of_range for a bad index.
  void SetMovingPose(int index, const Eigen::Isometry3d& X_WI);

  /// Moves every moving object at once, `X_WI[k]` the pose of object k, with one rebuild of the
  /// scene's top level for all of them (none when none moved): per physics step, rather than one
  /// rebuild per object. @throws std::out_of_range unless there is one pose per moving object.
  void SetMovingPoses(const std::vector<Eigen::Isometry3d>& X_WI);

  /// Casts rays from one origin along unit `directions_W`, reporting the first hit in
  /// [0, range_max_m]: ray k's result is entry k of `hits`, which grows when it has fewer entries
  /// than rays and is never shrunk (no allocation in steady use).
  /// Uses `num_threads` threads for batches of 4096 rays or more. The scenes are not built
  /// robust (RTC_SCENE_FLAG_ROBUST would cost 19 % per frame): a ray exactly through an edge shared
  /// by two triangles can slip through, about 1 ray in 10,000 against a tessellated sphere, and
  /// counts as a miss, as a rare dropped return of a real sensor would.
  void Cast(const Eigen::Vector3f& origin_W, const Eigen::Ref<const Eigen::Matrix3Xf>& directions_W,
            float range_max_m, RayHits* hits, int num_threads = 1) const;

 private:
  struct Embree;
  // Sets the transform of moving object `index` without committing; false when unchanged.
  bool PlaceMoving(int index, const Eigen::Isometry3d& X_WI);
  void CastRange(const Eigen::Vector3f& origin_W,
                 const Eigen::Ref<const Eigen::Matrix3Xf>& directions_W, float range_max_m,
                 Eigen::Index begin, Eigen::Index end, RayHits* hits) const;
  std::unique_ptr<Embree> embree_;
  int num_objects_{0};
  std::vector<float> reflectance_;  // per object
};

}  // namespace trav::lidar
