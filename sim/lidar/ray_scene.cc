#include "sim/lidar/ray_scene.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include <embree3/rtcore.h>

namespace trav::lidar {

std::string EmbreeVersion() { return RTC_VERSION_STRING; }

namespace {

// Embree reports errors through a callback; the first one is kept and thrown by CheckDevice.
struct ErrorRecord {
  RTCError code{RTC_ERROR_NONE};
  std::string message;
};

void RecordError(void* user, RTCError code, const char* message) {
  auto* record = static_cast<ErrorRecord*>(user);
  if (record->code != RTC_ERROR_NONE) return;
  record->code = code;
  record->message = message != nullptr ? message : "";
}

constexpr Eigen::Index kParallelThreshold = 4096;

}  // namespace

struct RayScene::Embree {
  RTCDevice device{nullptr};
  RTCScene static_scene{nullptr};  // terrain and primitives, instanced once with identity
  RTCScene top_scene{nullptr};     // instances only: cheap to recommit when a pose changes
  std::vector<RTCScene> moving_scenes;
  std::vector<RTCGeometry> moving_instances;
  std::vector<Eigen::Isometry3d> moving_poses;  // each moving instance's pose, as last set
  std::vector<unsigned> moving_instance_ids;    // moving object index -> top-scene instance id
  std::vector<int> static_object_of_geometry;   // static geometry id -> object id
  std::vector<int> object_of_instance;          // top-scene instance id -> object id (-1: static)
  std::vector<Eigen::Matrix3f> rotation_of_instance;  // to turn instance-space normals into W
  ErrorRecord error;

  ~Embree() {
    if (top_scene != nullptr) rtcReleaseScene(top_scene);
    for (RTCScene scene : moving_scenes) rtcReleaseScene(scene);
    if (static_scene != nullptr) rtcReleaseScene(static_scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  void CheckDevice(const char* what) {
    if (error.code == RTC_ERROR_NONE) return;
    throw std::runtime_error(std::string("Embree error while ") + what + ": " + error.message +
                             " (code " + std::to_string(static_cast<int>(error.code)) + ")");
  }

  // Attaches a triangle mesh to `scene` and returns its geometry id.
  unsigned AttachMesh(RTCScene scene, const common::TriangleMesh& mesh) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), static_cast<size_t>(mesh.vertices.cols())));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), static_cast<size_t>(mesh.triangles.cols())));
    CheckDevice("allocating a mesh");
    std::memcpy(vertices, mesh.vertices.data(), sizeof(float) * 3 * mesh.vertices.cols());
    for (Eigen::Index i = 0; i < mesh.triangles.size(); ++i) {
      indices[i] = static_cast<unsigned>(mesh.triangles.data()[i]);
    }
    return Attach(scene, geometry);
  }

  // Attaches a sphere of `radius_m` about `centre_W` (Embree's sphere point) to `scene`; returns
  // its geometry id.
  unsigned AttachSphere(RTCScene scene, const Eigen::Vector3d& centre_W, float radius_m) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* vertex = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    CheckDevice("allocating a sphere");
    Eigen::Vector4f sphere;
    sphere << centre_W.cast<float>(), radius_m;
    std::memcpy(vertex, sphere.data(), sizeof(sphere));
    return Attach(scene, geometry);
  }

  // Commits `geometry`, attaches it to `scene` and returns its id.
  static unsigned Attach(RTCScene scene, RTCGeometry geometry) {
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    return id;
  }

  // Attaches a primitive to `scene` and returns its geometry id: a sphere on its exact surface
  // (Embree's sphere point), the other shapes as triangles, `segments` around. A frame among a
  // forest's 200 crowns casts about 27 % faster than with each crown as 2,256 triangles
  // (BM_EmbreeForestFrame); Embree's capped cone curves for cylinders (exact too) cast among the
  // ruin's 60 columns 75 % slower than their triangles, so cylinders and capsules stay meshes.
  unsigned AttachPrimitive(RTCScene scene, const common::Primitive& primitive, int segments) {
    if (primitive.shape == common::ShapeType::kSphere) {
      return AttachSphere(scene, primitive.X_WO.translation(),
                          static_cast<float>(primitive.size.x()));
    }
    return AttachMesh(scene, common::PrimitiveMesh(primitive, segments));
  }

  // Attaches an instance of `child` to the top scene; returns its geometry (owned by the caller)
  // and its id in `instance_id`.
  RTCGeometry AttachInstance(RTCScene child, const Eigen::Isometry3d& X_WI, int object_id,
                             unsigned* instance_id) {
    RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, child);
    SetTransform(instance, X_WI);
    const unsigned id = rtcAttachGeometry(top_scene, instance);
    if (object_of_instance.size() <= id) {
      object_of_instance.resize(id + 1, -1);
      rotation_of_instance.resize(id + 1, Eigen::Matrix3f::Identity());
    }
    object_of_instance[id] = object_id;
    rotation_of_instance[id] = X_WI.linear().cast<float>();
    *instance_id = id;
    return instance;
  }

  static void SetTransform(RTCGeometry instance, const Eigen::Isometry3d& X_WI) {
    const Eigen::Matrix<float, 3, 4> transform = X_WI.matrix().topRows<3>().cast<float>();
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform.data());
    rtcCommitGeometry(instance);
  }
};

RayScene::RayScene(const RaySceneDescription& description) : embree_(std::make_unique<Embree>()) {
  const std::size_t objects = description.meshes_W.size() + description.primitives_W.size() +
                              description.moving_meshes_I.size();
  if (!description.reflectance.empty() && description.reflectance.size() != objects) {
    throw std::invalid_argument(
        "RaySceneDescription: " + std::to_string(description.reflectance.size()) +
        " reflectances for " + std::to_string(objects) + " objects");
  }
  Embree& e = *embree_;
  // BVH builds on the calling thread: the top level is rebuilt every physics step for the movers,
  // and Embree's TBB workers, started for each of those small builds, spun on both cores (14 % of
  // the CPU of a run among 20 walkers); the static scene is built once. Rays are cast on threads
  // of our own (Cast), which this does not limit.
  e.device = rtcNewDevice("threads=1");
  if (e.device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  rtcSetDeviceErrorFunction(e.device, RecordError, &e.error);

  // static geometry: one child scene of medium build quality (binned SAH, no spatial splits). On
  // terrains of small, even triangles the high quality's splits bought no faster casts (a MID-360
  // frame 4.55 ms medium against 4.76 ms high on the benchmark's ruin) but cost 0.8 s of CPU in
  // every run's setup on the 500,000-triangle forest; the hits are the same (the 9 suite runs
  // bit-identical either way, docs/performance.md).
  e.static_scene = rtcNewScene(e.device);
  rtcSetSceneBuildQuality(e.static_scene, RTC_BUILD_QUALITY_MEDIUM);
  int object = 0;
  auto record_static = [&](unsigned id) {
    if (e.static_object_of_geometry.size() <= id) e.static_object_of_geometry.resize(id + 1, -1);
    e.static_object_of_geometry[id] = object++;
  };
  for (const common::TriangleMesh& mesh : description.meshes_W) {
    record_static(e.AttachMesh(e.static_scene, mesh));
  }
  for (const common::Primitive& primitive : description.primitives_W) {
    record_static(e.AttachPrimitive(e.static_scene, primitive, description.primitive_segments));
  }
  rtcCommitScene(e.static_scene);
  e.CheckDevice("building the static scene");

  // top scene: the static scene once, then every moving object
  e.top_scene = rtcNewScene(e.device);
  rtcSetSceneFlags(e.top_scene, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(e.top_scene, RTC_BUILD_QUALITY_LOW);
  unsigned instance_id = 0;
  rtcReleaseGeometry(
      e.AttachInstance(e.static_scene, Eigen::Isometry3d::Identity(), -1, &instance_id));
  if (description.X_WI.size() != description.moving_meshes_I.size()) {
    throw std::invalid_argument("RaySceneDescription: one pose X_WI per moving mesh is required");
  }
  for (std::size_t k = 0; k < description.moving_meshes_I.size(); ++k) {
    RTCScene child = rtcNewScene(e.device);
    e.AttachMesh(child, description.moving_meshes_I[k]);
    rtcCommitScene(child);
    e.moving_scenes.push_back(child);
    e.moving_instances.push_back(
        e.AttachInstance(child, description.X_WI[k], object++, &instance_id));
    e.moving_poses.push_back(description.X_WI[k]);
    e.moving_instance_ids.push_back(instance_id);
  }
  rtcCommitScene(e.top_scene);
  e.CheckDevice("building the scene");
  num_objects_ = object;
  reflectance_ =
      description.reflectance.empty()
          ? std::vector<float>(static_cast<std::size_t>(num_objects_), kDefaultReflectance)
          : description.reflectance;
}

RayScene::~RayScene() {
  if (embree_) {
    for (RTCGeometry instance : embree_->moving_instances) rtcReleaseGeometry(instance);
  }
}

bool RayScene::PlaceMoving(int index, const Eigen::Isometry3d& X_WI) {
  Embree& e = *embree_;
  if (index < 0 || index >= static_cast<int>(e.moving_instances.size())) {
    throw std::out_of_range("RayScene: no moving object " + std::to_string(index));
  }
  const auto k = static_cast<std::size_t>(index);
  if (e.moving_poses[k].matrix() == X_WI.matrix()) return false;  // exactly where it is
  e.moving_poses[k] = X_WI;
  Embree::SetTransform(e.moving_instances[k], X_WI);
  e.rotation_of_instance[e.moving_instance_ids[k]] = X_WI.linear().cast<float>();
  return true;
}

void RayScene::SetMovingPose(int index, const Eigen::Isometry3d& X_WI) {
  if (!PlaceMoving(index, X_WI)) return;
  rtcCommitScene(embree_->top_scene);
  embree_->CheckDevice("moving an object");
}

void RayScene::SetMovingPoses(const std::vector<Eigen::Isometry3d>& X_WI) {
  if (static_cast<int>(X_WI.size()) != num_moving()) {
    throw std::out_of_range("RayScene: " + std::to_string(X_WI.size()) + " poses for " +
                            std::to_string(num_moving()) + " moving objects");
  }
  bool moved = false;
  for (std::size_t k = 0; k < X_WI.size(); ++k) {
    moved = PlaceMoving(static_cast<int>(k), X_WI[k]) || moved;
  }
  if (!moved) return;
  // one commit of the top scene for every pose (a commit starts a BVH build on Embree's threads)
  rtcCommitScene(embree_->top_scene);
  embree_->CheckDevice("moving objects");
}

int RayScene::num_moving() const { return static_cast<int>(embree_->moving_instances.size()); }

void RayScene::Cast(const Eigen::Vector3f& origin_W,
                    const Eigen::Ref<const Eigen::Matrix3Xf>& directions_W, float range_max_m,
                    RayHits* hits, int num_threads) const {
  const Eigen::Index n = directions_W.cols();
  if (hits->range_m.size() < n) {
    hits->range_m.resize(n);
    hits->object_id.resize(n);
    hits->normal_W.resize(3, n);
  }
  if (num_threads <= 1 || n < kParallelThreshold) {
    CastRange(origin_W, directions_W, range_max_m, 0, n, hits);
    return;
  }
  // contiguous chunks, one per thread; each ray's result is independent of the split
  std::vector<std::thread> workers;
  const Eigen::Index chunk = (n + num_threads - 1) / num_threads;
  for (int t = 1; t < num_threads; ++t) {
    const Eigen::Index begin = std::min(n, t * chunk);
    const Eigen::Index end = std::min(n, begin + chunk);
    workers.emplace_back([=] { CastRange(origin_W, directions_W, range_max_m, begin, end, hits); });
  }
  CastRange(origin_W, directions_W, range_max_m, 0, std::min(n, chunk), hits);
  for (std::thread& worker : workers) worker.join();
}

void RayScene::CastRange(const Eigen::Vector3f& origin_W,
                         const Eigen::Ref<const Eigen::Matrix3Xf>& directions_W, float range_max_m,
                         Eigen::Index begin, Eigen::Index end, RayHits* hits) const {
  const Embree& e = *embree_;
  // without moving objects the static scene is the whole world: cast into it directly, sparing
  // every ray the instance level (the identity instance changes no ray, hit or normal)
  const bool direct = e.moving_instances.empty();
  RTCScene scene = direct ? e.static_scene : e.top_scene;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // packets of 16 rays: consecutive scan rays point almost the same way, so packets traverse the
  // BVH together (Embree requires 64-byte alignment of the packet and its mask)
  alignas(64) RTCRayHit16 packet;
  alignas(64) int valid[16];
  for (Eigen::Index first = begin; first < end; first += 16) {
    const int count = static_cast<int>(std::min<Eigen::Index>(16, end - first));
    for (int j = 0; j < 16; ++j) {
      const Eigen::Index i = first + std::min(j, count - 1);
      valid[j] = j < count ? -1 : 0;
      packet.ray.org_x[j] = origin_W.x();
      packet.ray.org_y[j] = origin_W.y();
      packet.ray.org_z[j] = origin_W.z();
      packet.ray.dir_x[j] = directions_W(0, i);
      packet.ray.dir_y[j] = directions_W(1, i);
      packet.ray.dir_z[j] = directions_W(2, i);
      packet.ray.tnear[j] = 0.0f;
      packet.ray.tfar[j] = range_max_m;
      packet.ray.time[j] = 0.0f;
      packet.ray.mask[j] = 0xFFFFFFFFu;
      packet.ray.id[j] = static_cast<unsigned>(j);
      packet.ray.flags[j] = 0;
      packet.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, scene, &context, &packet);

    for (int j = 0; j < count; ++j) {
      const Eigen::Index i = first + j;
      if (packet.hit.geomID[j] == RTC_INVALID_GEOMETRY_ID) {
        hits->range_m[i] = std::numeric_limits<float>::infinity();
        hits->object_id[i] = -1;
        hits->normal_W.col(i).setZero();
        continue;
      }
      const unsigned instance = packet.hit.instID[0][j];
      const int moving_object = direct ? -1 : e.object_of_instance[instance];
      hits->range_m[i] = packet.ray.tfar[j];
      hits->object_id[i] =
          moving_object >= 0 ? moving_object : e.static_object_of_geometry[packet.hit.geomID[j]];
      // Ng is in the instanced object's space and unnormalised
      Eigen::Vector3f normal(packet.hit.Ng_x[j], packet.hit.Ng_y[j], packet.hit.Ng_z[j]);
      if (!direct) normal = e.rotation_of_instance[instance] * normal;
      normal.normalize();
      // face the ray (meshes are hit from both sides)
      if (normal.dot(directions_W.col(i)) > 0.0f) normal = -normal;
      hits->normal_W.col(i) = normal;
    }
  }
}

}  // namespace trav::lidar
