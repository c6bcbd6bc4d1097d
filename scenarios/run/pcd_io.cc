#include "scenarios/run/pcd_io.h"

#include <cstdint>
#include <stdexcept>

#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "common/input_error.h"

// A LiDAR point with its time offset, laser line, reflectivity and tag, as Livox drivers publish
// them. PCL's point
// macro declares an anonymous struct in a union, which clang flags as an extension.
#if defined(__clang__)
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wgnu-anonymous-struct"
#pragma clang diagnostic ignored "-Wnested-anon-types"
#endif
struct EIGEN_ALIGN16 TravLidarPoint {
  PCL_ADD_POINT4D;
  float time;
  std::uint16_t line;
  std::uint8_t reflectivity;
  std::uint8_t tag;
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};
#if defined(__clang__)
#pragma clang diagnostic pop
#endif
POINT_CLOUD_REGISTER_POINT_STRUCT(TravLidarPoint,
                                  (float, x, x)(float, y, y)(float, z, z)(float, time, time)(
                                      std::uint16_t, line, line)(std::uint8_t, reflectivity,
                                                                 reflectivity)(std::uint8_t, tag,
                                                                               tag))

namespace trav::scenarios {

void WritePcd(const std::string& path, const common::PointCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZ> pcl_cloud;
  pcl_cloud.resize(static_cast<std::size_t>(cloud.size()));
  for (Eigen::Index i = 0; i < cloud.size(); ++i) {
    pcl_cloud[static_cast<std::size_t>(i)] =
        pcl::PointXYZ(cloud.points(0, i), cloud.points(1, i), cloud.points(2, i));
  }
  if (pcl::io::savePCDFileBinary(path, pcl_cloud) != 0)
    throw common::InputError(path, "", "cannot write");
}

void WriteLidarFramePcd(const std::string& path, const lidar::LidarFrame& frame) {
  const common::PointCloud& cloud = frame.points_L;
  pcl::PointCloud<TravLidarPoint> pcl_cloud;
  pcl_cloud.resize(static_cast<std::size_t>(cloud.size()));
  for (Eigen::Index i = 0; i < cloud.size(); ++i) {
    TravLidarPoint& point = pcl_cloud[static_cast<std::size_t>(i)];
    point.x = cloud.points(0, i);
    point.y = cloud.points(1, i);
    point.z = cloud.points(2, i);
    point.time = cloud.time_offsets[i];
    point.line = static_cast<std::uint16_t>(cloud.line_ids[i]);
    point.reflectivity = cloud.reflectivity[i];
    point.tag = cloud.tags[i];
  }
  const Eigen::Isometry3d& X_WL = frame.X_WL_start();
  pcl_cloud.sensor_origin_ = Eigen::Vector4f(static_cast<float>(X_WL.translation().x()),
                                             static_cast<float>(X_WL.translation().y()),
                                             static_cast<float>(X_WL.translation().z()), 0.0f);
  pcl_cloud.sensor_orientation_ = Eigen::Quaternionf(X_WL.linear().cast<float>());
  if (pcl::io::savePCDFileBinary(path, pcl_cloud) != 0)
    throw common::InputError(path, "", "cannot write");
}

}  // namespace trav::scenarios
