#pragma once

#include <memory>

#include "mapping/traversability_mapper.h"
#include "scenarios/run/scenario.h"

namespace trav::scenarios {

/// The mapper a scenario asks for (`mapping.method`, scenarios/run/plugins.h), configured from its
/// `mapping` keys: fsgp-bgk; fsgp (no fusion); fsgp-accumulation (no fusion, `accumulate_frames`
/// frames, 5 if left at 1); sgp and em with the same window, resolution and map size; a registered
/// mapper; null for the ground-truth oracle (no mapper: the runner uses the ground truth itself).
/// On an estimated pose (`pose_noise.active()`) without the steps against the cells' floors
/// (`mapping.floor_steps` false, mapping::MapArea).
/// @throws common::InputError if the method is not registered.
std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario);

}  // namespace trav::scenarios
