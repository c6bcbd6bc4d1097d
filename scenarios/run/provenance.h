#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace trav::scenarios {

/// What produced a result, for summary.json's `provenance`: trav's version and git commit, the
/// build type and compiler, the MuJoCo, Embree and Ceres versions, and the hash of the resolved
/// scenario text (`scenario_yaml`), so that two summaries can be told to come from the same
/// inputs and code.
nlohmann::json Provenance(const std::string& scenario_yaml);

/// What `trav --version` prints: trav's version and commit, the build, and the versions of the
/// libraries that decide a run (MuJoCo, Embree, Ceres).
std::string VersionText();

/// The 64-bit FNV-1a hash of `text` as "fnv1a64:<16 hex digits>".
std::string TextHash(const std::string& text);

}  // namespace trav::scenarios
