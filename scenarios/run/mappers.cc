#include "scenarios/run/mappers.h"

#include "scenarios/run/plugins.h"

namespace trav::scenarios {

std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario) {
  return FindMapper(scenario.mapper)(scenario);
}

}  // namespace trav::scenarios
