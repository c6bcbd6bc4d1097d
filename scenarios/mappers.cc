#include "scenarios/mappers.h"

#include "mapping/baselines.h"
#include "mapping/fsgp_bgk_mapper.h"

namespace trav::scenarios {

std::unique_ptr<mapping::TraversabilityMapper> MakeMapper(const Scenario& scenario) {
  mapping::FsgpConfig fsgp = scenario.mapping;
  switch (scenario.mapper) {
    case MapperMethod::kFsgpBgk:
      return std::make_unique<mapping::FsgpBgkMapper>(fsgp);
    case MapperMethod::kFsgp:
      fsgp.fuse = false;
      return std::make_unique<mapping::FsgpBgkMapper>(fsgp);
    case MapperMethod::kFsgpAccumulation:
      fsgp.fuse = false;
      if (fsgp.accumulate_frames == 1) fsgp.accumulate_frames = 5;
      return std::make_unique<mapping::FsgpBgkMapper>(fsgp);
    case MapperMethod::kSgp: {
      mapping::SgpConfig sgp;
      sgp.window_m = fsgp.window_m;
      sgp.resolution_m = fsgp.resolution_m;
      sgp.map_size_m = fsgp.map_size_m;
      sgp.max_height_above_robot_m = fsgp.max_height_above_robot_m;
      return std::make_unique<mapping::SgpMapper>(sgp);
    }
    case MapperMethod::kElevationMap: {
      mapping::ElevationMapConfig em;
      em.window_m = fsgp.window_m;
      em.resolution_m = fsgp.resolution_m;
      em.map_size_m = fsgp.map_size_m;
      em.max_height_above_robot_m = fsgp.max_height_above_robot_m;
      return std::make_unique<mapping::ElevationMapper>(em, fsgp);
    }
  }
  return std::make_unique<mapping::FsgpBgkMapper>(fsgp);
}

}  // namespace trav::scenarios
