#pragma once

#include <memory>

#include "mapping/traversability_mapper.h"
#include "scenarios/run/scenario.h"

namespace trav::scenarios {

/// The mapper a scenario asks for (`mapping.method`), configured from its `mapping` keys: fsgp-bgk;
/// fsgp (no fusion); fsgp-accumulation (no fusion, `accumulate_frames` frames, 5 if left at 1); sgp
/// and em with the same window, resolution and map size; null for the ground-truth oracle (no
/// mapper: the runner uses the ground truth itself).
std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario);

}  // namespace trav::scenarios
