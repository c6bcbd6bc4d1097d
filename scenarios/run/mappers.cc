#include "scenarios/run/mappers.h"

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
      sgp.area = fsgp.area;
      // M: the inducing points of every GP mapper
      sgp.inducing_points = fsgp.max_training_points;
      return std::make_unique<mapping::SgpMapper>(sgp);
    }
    case MapperMethod::kElevationMap: {
      mapping::ElevationMapConfig em;
      em.area = fsgp.area;
      return std::make_unique<mapping::ElevationMapper>(em, fsgp);
    }
    case MapperMethod::kGroundTruth:
      return nullptr;
  }
  return std::make_unique<mapping::FsgpBgkMapper>(fsgp);
}

}  // namespace trav::scenarios
