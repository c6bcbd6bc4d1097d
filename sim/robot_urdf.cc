// The robot file as URDF (sim::RobotUrdf), from the model MuJoCo compiles.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <mujoco/mujoco.h>

#include "common/input_error.h"
#include "common/input_file.h"
#include "common/pose.h"
#include "sim/simulation.h"

namespace trav::sim {
namespace {

// The URDF name of body `b`: REP-105's base_link for the robot's base.
std::string LinkName(const mjModel* m, int b) {
  const std::string name = mj_id2name(m, mjOBJ_BODY, b) ? mj_id2name(m, mjOBJ_BODY, b) : "";
  if (name == "base") return "base_link";
  return name.empty() ? fmt::format("body_{}", b) : name;
}

Eigen::Isometry3d Pose(const mjtNum* pos, const mjtNum* quat) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << pos[0], pos[1], pos[2];
  X.linear() = Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).toRotationMatrix();
  return X;
}

std::string Origin(const Eigen::Isometry3d& X) {
  const common::RollPitchYaw rpy = common::ToRollPitchYaw(X.linear());
  const Eigen::Vector3d p = X.translation();
  // + 0.0 turns -0 into 0
  return fmt::format(R"(<origin xyz="{:.6g} {:.6g} {:.6g}" rpy="{:.6g} {:.6g} {:.6g}"/>)",
                     p.x() + 0.0, p.y() + 0.0, p.z() + 0.0, rpy.roll + 0.0, rpy.pitch + 0.0,
                     rpy.yaw + 0.0);
}

// The <geometry> of geom `g` and the pose of that geometry in the geom's frame.
std::string Geometry(const mjModel* m, int g, const std::string& file, Eigen::Isometry3d* X_GS) {
  const mjtNum* s = m->geom_size + 3 * g;
  *X_GS = Eigen::Isometry3d::Identity();
  switch (m->geom_type[g]) {
    case mjGEOM_BOX:
      return fmt::format(R"(<box size="{:.6g} {:.6g} {:.6g}"/>)", 2 * s[0], 2 * s[1], 2 * s[2]);
    case mjGEOM_SPHERE:
      return fmt::format(R"(<sphere radius="{:.6g}"/>)", s[0]);
    case mjGEOM_CYLINDER:
    case mjGEOM_CAPSULE:  // URDF has no capsule: the cylinder of its body
      return fmt::format(R"(<cylinder radius="{:.6g}" length="{:.6g}"/>)", s[0], 2 * s[1]);
    case mjGEOM_ELLIPSOID: {
      // a disc of two equal semi-axes (URDF cylinders run along z): turn its third axis onto z
      for (int axis = 0; axis < 3; ++axis) {
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        if (std::abs(s[a] - s[b]) > 1e-9) continue;
        if (axis == 0)
          X_GS->linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
        if (axis == 1)
          X_GS->linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
        return fmt::format(R"(<cylinder radius="{:.6g}" length="{:.6g}"/>)", s[a], 2 * s[axis]);
      }
      return fmt::format(R"(<box size="{:.6g} {:.6g} {:.6g}"/>)", 2 * s[0], 2 * s[1], 2 * s[2]);
    }
    default:
      throw common::InputError(file, "",
                               fmt::format("geom {} is a shape URDF cannot say (a mesh, plane or "
                                           "height field)",
                                           g));
  }
}

void WriteLink(const mjModel* m, int b, const std::string& file, std::ostringstream* out) {
  *out << "  <link name=\"" << LinkName(m, b) << "\">\n";
  if (m->body_mass[b] > 0.0) {
    const mjtNum* inertia = m->body_inertia + 3 * b;
    *out
        << "    <inertial>\n      " << Origin(Pose(m->body_ipos + 3 * b, m->body_iquat + 4 * b))
        << "\n"
        << fmt::format(R"(      <mass value="{:.6g}"/>)", m->body_mass[b]) << "\n"
        << fmt::format(
               R"(      <inertia ixx="{:.6g}" ixy="0" ixz="0" iyy="{:.6g}" iyz="0" izz="{:.6g}"/>)",
               inertia[0], inertia[1], inertia[2])
        << "\n    </inertial>\n";
  }
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] != b) continue;
    Eigen::Isometry3d X_GS;
    const std::string geometry = Geometry(m, g, file, &X_GS);
    const std::string origin = Origin(Pose(m->geom_pos + 3 * g, m->geom_quat + 4 * g) * X_GS);
    // a geom that collides is collision geometry, and visual too when MuJoCo shows it by default
    // (groups 0 to 2); one that does not collide is visual only
    const bool collides = m->geom_contype[g] != 0 || m->geom_conaffinity[g] != 0;
    const bool shown = m->geom_group[g] < 3;
    for (const char* kind : {"collision", "visual"}) {
      const bool collision = std::string(kind) == "collision";
      if ((collision && !collides) || (!collision && collides && !shown)) continue;
      *out << "    <" << kind << ">\n      " << origin << "\n      <geometry>" << geometry
           << "</geometry>\n    </" << kind << ">\n";
    }
  }
  *out << "  </link>\n";
}

void WriteJoint(const mjModel* m, int b, const std::string& file, std::ostringstream* out) {
  const std::string parent = LinkName(m, m->body_parentid[b]);
  const std::string child = LinkName(m, b);
  const std::string origin = Origin(Pose(m->body_pos + 3 * b, m->body_quat + 4 * b));
  if (m->body_jntnum[b] == 0) {
    *out << fmt::format(
        "  <joint name=\"{}_fixed\" type=\"fixed\">\n    <parent link=\"{}\"/>\n    <child "
        "link=\"{}\"/>\n    {}\n  </joint>\n",
        child, parent, child, origin);
    return;
  }
  const int j = m->body_jntadr[b];
  const int type = m->jnt_type[j];
  if (m->body_jntnum[b] > 1 || (type != mjJNT_HINGE && type != mjJNT_SLIDE)) {
    throw common::InputError(file, "",
                             "body '" + child +
                                 "' has a joint URDF cannot say (several joints, a "
                                 "ball or a free joint below the base)");
  }
  const bool limited = m->jnt_limited[j] != 0;
  const char* urdf_type = type == mjJNT_SLIDE ? "prismatic" : (limited ? "revolute" : "continuous");
  const mjtNum* axis = m->jnt_axis + 3 * j;
  *out << fmt::format(
      "  <joint name=\"{}\" type=\"{}\">\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n"
      "    {}\n    <axis xyz=\"{:.6g} {:.6g} {:.6g}\"/>\n",
      mj_id2name(m, mjOBJ_JOINT, j), urdf_type, parent, child, origin, axis[0], axis[1], axis[2]);
  // the joint's actuator force limit, if a motor drives it (URDF requires an effort limit)
  double effort = 0.0;
  for (int a = 0; a < m->nu; ++a) {
    if (m->actuator_trnid[2 * a] == j && m->actuator_forcelimited[a]) {
      effort = std::max(std::abs(m->actuator_forcerange[2 * a]),
                        std::abs(m->actuator_forcerange[2 * a + 1]));
    }
  }
  if (limited || type == mjJNT_SLIDE || effort > 0.0) {
    *out << fmt::format(
                R"(    <limit lower="{:.6g}" upper="{:.6g}" effort="{:.6g}" velocity="0"/>)",
                limited ? m->jnt_range[2 * j] : 0.0, limited ? m->jnt_range[2 * j + 1] : 0.0,
                effort)
         << "\n";
  }
  *out << fmt::format(R"(    <dynamics damping="{:.6g}"/>)", m->dof_damping[m->jnt_dofadr[j]])
       << "\n  </joint>\n";
}

// A fixed link at each site (the sensors' frames).
void WriteSites(const mjModel* m, std::ostringstream* out) {
  for (int s = 0; s < m->nsite; ++s) {
    const char* name = mj_id2name(m, mjOBJ_SITE, s);
    if (name == nullptr) continue;
    *out << fmt::format(
        "  <link name=\"{}\"/>\n  <joint name=\"{}_fixed\" type=\"fixed\">\n    <parent "
        "link=\"{}\"/>\n    <child link=\"{}\"/>\n    {}\n  </joint>\n",
        name, name, LinkName(m, m->site_bodyid[s]), name,
        Origin(Pose(m->site_pos + 3 * s, m->site_quat + 4 * s)));
  }
}

}  // namespace

std::string RobotUrdf(const std::string& robot_model_path) {
  // loaded once, as it is (the names trav drives by are not needed to describe it)
  InstallMujocoHandlers();
  common::RequireRegularFile(robot_model_path, "robot model");
  char error[1024] = "";
  std::unique_ptr<mjModel, decltype(&mj_deleteModel)> model(nullptr, mj_deleteModel);
  try {
    model.reset(mj_loadXML(robot_model_path.c_str(), nullptr, error, sizeof(error)));
  } catch (const std::runtime_error& e) {
    throw common::InputError(robot_model_path, "", std::string("does not load: ") + e.what());
  }
  if (!model) {
    throw common::InputError(robot_model_path, "", std::string("does not load: ") + error);
  }
  const mjModel* m = model.get();
  int roots = 0;
  for (int b = 1; b < m->nbody; ++b) roots += m->body_parentid[b] == 0 ? 1 : 0;
  if (roots != 1) {
    throw common::InputError(robot_model_path, "",
                             "has several bodies in the world; a URDF has one root link");
  }
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<!-- Generated by `trav urdf` from the MuJoCo model "
      << std::filesystem::path(robot_model_path).filename().string()
      << " (masses and inertias as MuJoCo computes them); do not edit. -->\n";
  // the model's name is the first of the names
  out << "<robot name=\"" << m->names << "\">\n";
  // the base (the world's child, with the free joint) and every body below it
  for (int b = 1; b < m->nbody; ++b) {
    WriteLink(m, b, robot_model_path, &out);
    if (m->body_parentid[b] != 0) WriteJoint(m, b, robot_model_path, &out);
  }
  WriteSites(m, &out);
  out << "</robot>\n";
  return out.str();
}

}  // namespace trav::sim
