#include "scenarios/run/mappers.h"

#include "scenarios/run/plugins.h"

namespace trav::scenarios {

std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario,
                                                          MapperPose pose) {
  if (pose == MapperPose::kTrue) return FindMapper(scenario.mapper)(scenario);
  Scenario estimated = scenario;
  estimated.mapping.area.floor_steps = false;
  return FindMapper(scenario.mapper)(estimated);
}

std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario) {
  return MakeMapper(scenario,
                    scenario.pose_noise.active() ? MapperPose::kEstimated : MapperPose::kTrue);
}

}  // namespace trav::scenarios
