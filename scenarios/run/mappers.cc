#include "scenarios/run/mappers.h"

#include "scenarios/run/plugins.h"

namespace trav::scenarios {

std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario) {
  if (!scenario.pose_noise.active()) return FindMapper(scenario.mapper)(scenario);
  // on an estimated pose the cells' floors drift with its height: no steps against them
  Scenario estimated = scenario;
  estimated.mapping.area.floor_steps = false;
  return FindMapper(scenario.mapper)(estimated);
}

}  // namespace trav::scenarios
