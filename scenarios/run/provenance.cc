#include "scenarios/run/provenance.h"

#include <cstdint>

#include <fmt/format.h>

#include "controller/mpc.h"
#include "scenarios/run/build_info.h"
#include "sim/lidar/ray_scene.h"
#include "sim/simulation.h"

namespace trav::scenarios {

std::string TextHash(const std::string& text) {
  std::uint64_t hash = 1469598103934665603ull;
  for (const char c : text) hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return fmt::format("fnv1a64:{:016x}", hash);
}

std::string VersionText() {
  return fmt::format("trav {} (commit {}, {} build, {})\nMuJoCo {}, Embree {}, Ceres {}",
                     TRAV_VERSION, TRAV_GIT_COMMIT, TRAV_BUILD_TYPE, TRAV_COMPILER,
                     sim::MujocoVersion(), lidar::EmbreeVersion(), controller::CeresVersion());
}

nlohmann::json Provenance(const std::string& scenario_yaml) {
  return {{"trav_version", TRAV_VERSION},
          {"trav_commit", TRAV_GIT_COMMIT},
          {"build_type", TRAV_BUILD_TYPE},
          {"compiler", TRAV_COMPILER},
          {"mujoco_version", sim::MujocoVersion()},
          {"embree_version", lidar::EmbreeVersion()},
          {"ceres_version", controller::CeresVersion()},
          {"scenario_hash", TextHash(scenario_yaml)}};
}

}  // namespace trav::scenarios
