#include "scenarios/run/mapping_pipeline.h"

#include <utility>

#include "common/check.h"
#include "common/stopwatch.h"

namespace trav::scenarios {

MappingPipeline::MappingPipeline(std::unique_ptr<mapping::TraversabilityMapper> mapper,
                                 bool worker_thread)
    : mapper_(std::move(mapper)) {
  TRAV_DEMAND(mapper_ != nullptr);
  if (worker_thread) {
    worker_ = std::make_unique<common::SerialWorker<MapInput, Done>>([this](MapInput& input) {
      return Done{Map(input), mapper_->map()};
    });
  }
}

MapUpdate MappingPipeline::Map(const MapInput& input) {
  const common::Stopwatch start;
  MapUpdate update;
  update.result = mapper_->Update(input.cloud_O, input.X_OB, input.scan_time_s);
  update.mapping_ms = start.ElapsedMilliseconds();
  return update;
}

void MappingPipeline::Submit(MapInput input) {
  TRAV_DEMAND(queued_ready_s_.empty() || queued_ready_s_.back() <= input.ready_s);
  queued_ready_s_.push_back(input.ready_s);
  if (threaded()) {
    worker_->Submit(std::move(input));
  } else {
    waiting_.push_back(std::move(input));
  }
}

std::optional<MapUpdate> MappingPipeline::NextDue(double now_s) {
  // the same tolerance for every frame, whichever thread maps it
  if (queued_ready_s_.empty() || queued_ready_s_.front() > now_s + 1e-9) return std::nullopt;
  queued_ready_s_.pop_front();
  if (!threaded()) {
    const MapUpdate update = Map(waiting_.front());
    waiting_.pop_front();
    map_ = &mapper_->map();
    return update;
  }
  Done done = worker_->TakeNext();
  handed_out_ = std::move(done.map);
  map_ = &handed_out_;
  return done.update;
}

}  // namespace trav::scenarios
