#include "sim/world_builder.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "common/text.h"

namespace trav::sim {
namespace {

const char* MjcfShape(ShapeType shape) {
  switch (shape) {
    case ShapeType::kBox:
      return "box";
    case ShapeType::kCylinder:
      return "cylinder";
    case ShapeType::kSphere:
      return "sphere";
    case ShapeType::kCapsule:
      return "capsule";
  }
  return "box";
}

std::string MjcfSize(const common::Primitive& primitive) {
  std::ostringstream out;
  out << std::setprecision(9);
  switch (primitive.shape) {
    case ShapeType::kBox:
      out << primitive.size.x() << " " << primitive.size.y() << " " << primitive.size.z();
      break;
    case ShapeType::kCylinder:
    case ShapeType::kCapsule:
      out << primitive.size.x() << " " << primitive.size.y();
      break;
    case ShapeType::kSphere:
      out << primitive.size.x();
      break;
  }
  return out.str();
}

// pos="x y z" quat="w x y z" of a pose.
std::string MjcfPose(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.linear());
  const Eigen::Vector3d p = X.translation();
  std::ostringstream out;
  out << std::setprecision(9) << "pos=\"" << p.x() << " " << p.y() << " " << p.z() << "\" quat=\""
      << q.w() << " " << q.x() << " " << q.y() << " " << q.z() << "\"";
  return out.str();
}

std::string MjcfRgba(const Eigen::Vector4f& rgba) {
  std::ostringstream out;
  out << std::setprecision(9) << "rgba=\"" << rgba[0] << " " << rgba[1] << " " << rgba[2] << " "
      << rgba[3] << "\"";
  return out.str();
}

}  // namespace

HeightFieldLayout ComputeHeightFieldLayout(const TerrainWorld& world) {
  HeightFieldLayout layout;
  layout.z_offset_m = world.height_m.minCoeff();
  layout.z_top_m =
      std::max(1e-3, static_cast<double>(world.height_m.maxCoeff()) - layout.z_offset_m);
  return layout;
}

Eigen::MatrixXf ResampleGround(const TerrainWorld& world, int max_samples) {
  const common::GridGeometry& full = world.geometry;
  const int num_x = std::min(full.num_x, max_samples);
  const int num_y = std::min(full.num_y, max_samples);
  if (num_x == full.num_x && num_y == full.num_y) return world.height_m;
  Eigen::MatrixXf height_m(num_x, num_y);
  const Eigen::Vector2d extent = full.Extent();
  for (int iy = 0; iy < num_y; ++iy) {
    for (int ix = 0; ix < num_x; ++ix) {
      const Eigen::Vector2d p = full.origin_W + Eigen::Vector2d(extent.x() * ix / (num_x - 1),
                                                                extent.y() * iy / (num_y - 1));
      height_m(ix, iy) = static_cast<float>(world.GroundHeight(p));
    }
  }
  return height_m;
}

void FillHeightField(const Eigen::MatrixXf& height_m, const HeightFieldLayout& layout,
                     float* data) {
  // Eigen's column-major (num_x, num_y) storage is row-major with rows along y: MuJoCo's layout.
  const Eigen::Index n = height_m.size();
  const float offset = static_cast<float>(layout.z_offset_m);
  const float scale = static_cast<float>(1.0 / layout.z_top_m);
  for (Eigen::Index i = 0; i < n; ++i) {
    data[i] = std::clamp((height_m.data()[i] - offset) * scale, 0.0f, 1.0f);
  }
}

namespace {

// An hfield asset: its samples filled from memory later (nrow x ncol), or read from `file`.
std::string HeightFieldAsset(const std::string& name, int nrow, int ncol,
                             const Eigen::Vector2d& half, const HeightFieldLayout& layout,
                             const std::string& file) {
  std::ostringstream xml;
  xml << std::setprecision(9) << "    <hfield name=\"" << name << "\" ";
  if (file.empty()) {
    xml << "nrow=\"" << nrow << "\" ncol=\"" << ncol << "\"";
  } else {
    xml << "file=\"" << common::EscapeMarkup(file) << "\"";
  }
  xml << " size=\"" << half.x() << " " << half.y() << " " << layout.z_top_m << " 1\"/>\n";
  return xml.str();
}

}  // namespace

std::string BuildWorldXml(const TerrainWorld& world, const WorldOptions& options,
                          const std::vector<MovingObstacle>& movers) {
  const HeightFieldLayout layout = ComputeHeightFieldLayout(world);
  const Eigen::Vector2d half = 0.5 * world.geometry.Extent();
  const Eigen::Vector2d centre = world.geometry.Center();
  const double far = 2.0 * world.geometry.Extent().norm() + 50.0;
  const int visual_num_x = std::min(world.geometry.num_x, options.visual_max_samples);
  const int visual_num_y = std::min(world.geometry.num_y, options.visual_max_samples);

  const std::string static_collision = " contype=\"" + std::to_string(kStaticContype) +
                                       "\" conaffinity=\"" + std::to_string(kCollidesWithRobot) +
                                       "\"";
  std::ostringstream xml;
  xml << std::setprecision(9);
  xml << "<mujoco model=\"trav_world\">\n"
      << "  <include file=\"" << common::EscapeMarkup(options.robot_model_path) << "\"/>\n"
      << "  <option timestep=\"" << options.timestep_s << "\"/>\n"
      << "  <visual>\n"
      << "    <quality shadowsize=\"1024\" offsamples=\"0\" numslices=\"12\" numstacks=\"8\"/>\n"
      << "    <map znear=\"0.01\" zfar=\"" << far << "\" haze=\"0.2\"/>\n"
      << "    <headlight ambient=\"0.25 0.25 0.25\" diffuse=\"0.25 0.25 0.25\"/>\n"
      << "    <rgba haze=\"0.75 0.82 0.9 1\"/>\n"
      << "  </visual>\n"
      << "  <asset>\n"
      << "    <texture name=\"sky\" type=\"skybox\" builtin=\"gradient\" rgb1=\"0.55 0.7 0.9\""
      << " rgb2=\"0.9 0.93 0.97\" width=\"64\" height=\"64\"/>\n"
      // the ground's colours, once over the whole terrain: a flat colour here, painted from the
      // heights by the video renderer (renders/ground_texture.h)
      << "    <texture name=\"" << kGroundTextureName << "\" type=\"2d\" builtin=\"flat\""
      << " rgb1=\"0.36 0.5 0.2\" width=\"" << kGroundTextureSize << "\" height=\""
      << kGroundTextureSize << "\"/>\n"
      << "    <material name=\"ground\" texture=\"" << kGroundTextureName
      << "\" texrepeat=\"1 1\" texuniform=\"false\" specular=\"0.05\"/>\n"
      << HeightFieldAsset("terrain", world.geometry.num_y, world.geometry.num_x, half, layout,
                          options.height_field_file)
      << HeightFieldAsset("terrain_visual", visual_num_y, visual_num_x, half, layout,
                          options.height_field_file)
      << "  </asset>\n"
      << "  <worldbody>\n"
      << "    <light name=\"sun\" directional=\"true\" pos=\"0 0 50\" dir=\"-0.5 0.35 -0.6\""
      << " diffuse=\"0.75 0.75 0.72\" castshadow=\"true\"/>\n"
      << "    <geom name=\"ground\" type=\"hfield\" hfield=\"terrain\" pos=\"" << centre.x() << " "
      << centre.y() << " " << layout.z_offset_m << "\" friction=\"" << options.ground_friction
      << " 0.005 0.0001\" group=\"3\"" << static_collision << "/>\n"
      << "    <geom name=\"ground_visual\" type=\"hfield\" hfield=\"terrain_visual\" pos=\""
      << centre.x() << " " << centre.y() << " " << layout.z_offset_m
      << "\" contype=\"0\" conaffinity=\"0\" material=\"ground\" group=\"0\"/>\n";
  for (const Obstacle& obstacle : world.obstacles) {
    xml << "    <geom name=\"" << obstacle.name << "\" type=\"" << MjcfShape(obstacle.shape)
        << "\" size=\"" << MjcfSize(obstacle) << "\" " << MjcfPose(obstacle.X_WO) << " "
        << MjcfRgba(obstacle.rgba) << " friction=\"" << options.ground_friction
        << " 0.005 0.0001\"";
    switch (obstacle.role) {
      case ObstacleRole::kSolid:
        xml << " group=\"0\"" << static_collision << "/>\n";
        break;
      case ObstacleRole::kCanopy:
        xml << " group=\"2\" contype=\"0\" conaffinity=\"0\"/>\n";
        break;
      case ObstacleRole::kCeiling:
        xml << " group=\"4\"" << static_collision << "/>\n";
        break;
    }
  }
  // movers: mocap bodies (kinematic; their poses are written into mjData every step)
  for (const MovingObstacle& mover : movers) {
    const common::Primitive primitive = MoverPrimitive(mover);
    xml << "    <body name=\"mover_" << mover.name << "\" mocap=\"true\" "
        << MjcfPose(MoverPoseAt(mover, 0.0, world)) << ">\n"
        << "      <geom name=\"mover_" << mover.name << "\" type=\"" << MjcfShape(primitive.shape)
        << "\" size=\"" << MjcfSize(primitive) << "\" " << MjcfRgba(mover.rgba) << " friction=\""
        << options.ground_friction << " 0.005 0.0001\" group=\"0\" contype=\"" << kMoverContype
        << "\" conaffinity=\"" << kCollidesWithRobot << "\"/>\n"
        << "    </body>\n";
  }
  xml << "  </worldbody>\n</mujoco>\n";
  return xml.str();
}

void WriteHeightFieldFile(const TerrainWorld& world, const std::string& path) {
  const Eigen::MatrixXf& height_m = world.height_m;
  std::vector<float> samples(static_cast<std::size_t>(height_m.size()));
  FillHeightField(height_m, ComputeHeightFieldLayout(world), samples.data());
  const std::int32_t size[2] = {static_cast<std::int32_t>(height_m.cols()),   // nrow: along y
                                static_cast<std::int32_t>(height_m.rows())};  // ncol: along x
  std::ofstream file(path, std::ios::binary);
  file.write(reinterpret_cast<const char*>(size), sizeof(size));
  file.write(reinterpret_cast<const char*>(samples.data()),
             static_cast<std::streamsize>(samples.size() * sizeof(float)));
  file.close();
  if (!file) throw std::runtime_error("cannot write the height field " + path);
}

void ExportWorld(const TerrainWorld& world, const WorldOptions& options,
                 const std::vector<MovingObstacle>& movers, const std::string& folder) {
  WorldOptions exported = options;
  exported.height_field_file = "terrain.bin";
  // MuJoCo reads an include relative to the including file: a robot file that names no other file
  // is copied beside world.xml (the folder then opens wherever it is moved); one with meshes or
  // textures is included where it is, by its path relative to the folder
  std::ifstream robot(options.robot_model_path);
  std::stringstream robot_xml;
  robot_xml << robot.rdbuf();
  if (robot_xml.str().find("file=") == std::string::npos &&
      robot_xml.str().find("dir=") == std::string::npos) {
    std::ofstream copy(folder + "/robot.xml");
    copy << robot_xml.str();
    copy.close();
    if (!copy) throw std::runtime_error("cannot write " + folder + "/robot.xml");
    exported.robot_model_path = "robot.xml";
  } else {
    exported.robot_model_path =
        std::filesystem::relative(options.robot_model_path, folder).string();
  }
  WriteHeightFieldFile(world, folder + "/terrain.bin");
  std::ofstream file(folder + "/world.xml");
  file << BuildWorldXml(world, exported, movers);
  file.close();
  if (!file) throw std::runtime_error("cannot write " + folder + "/world.xml");
}

}  // namespace trav::sim
