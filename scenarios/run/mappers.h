#pragma once

#include <memory>

#include "mapping/traversability_mapper.h"
#include "scenarios/run/scenario.h"

namespace trav::scenarios {

/// The pose a mapper's frames are registered with.
enum class MapperPose {
  kTrue,       ///< the simulator's true pose
  kEstimated,  ///< a localization's estimate, whose height drifts
};

/// The mapper a scenario asks for (`mapping.method`, scenarios/run/plugins.h), configured from its
/// `mapping` keys: fsgp-bgk; fsgp (no fusion); fsgp-accumulation (no fusion, `accumulate_frames`
/// frames, 5 if left at 1); sgp and em with the same window, resolution and map size; a registered
/// mapper; null for the ground-truth oracle (no mapper: the runner uses the ground truth itself).
/// On an estimated pose without the steps against the cells' floors (`mapping.floor_steps` false,
/// mapping::MapArea): the estimate's height drifts by more than the climbable step over a few
/// metres, and every cell seen before and after would read as a step.
/// @throws common::InputError if the method is not registered.
std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario,
                                                          MapperPose pose);

/// The mapper of a closed-loop run: on the estimated pose when the scenario's navigation runs on
/// one (`pose_noise.active()`), else on the true pose.
std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario);

}  // namespace trav::scenarios
