#include "scenarios/run/mapping_pipeline.h"

#include <utility>

#include "common/check.h"
#include "common/stopwatch.h"

namespace trav::scenarios {

MappingPipeline::MappingPipeline(std::unique_ptr<mapping::TraversabilityMapper> mapper,
                                 bool worker_thread)
    : mapper_(std::move(mapper)) {
  TRAV_DEMAND(mapper_ != nullptr);
  if (worker_thread) worker_ = std::thread([this] { Work(); });
}

MappingPipeline::~MappingPipeline() {
  if (!worker_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_one();
  worker_.join();
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
  if (!threaded()) {
    waiting_.push_back(std::move(input));
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    inbox_.push_back(std::move(input));
  }
  work_ready_.notify_one();
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
  std::unique_lock<std::mutex> lock(mutex_);
  done_ready_.wait(lock, [this] { return !done_.empty() || error_ != nullptr; });
  if (done_.empty()) std::rethrow_exception(error_);
  Done done = std::move(done_.front());
  done_.pop_front();
  lock.unlock();
  handed_out_ = std::move(done.map);
  map_ = &handed_out_;
  return done.update;
}

void MappingPipeline::Work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_ready_.wait(lock, [this] { return stop_ || !inbox_.empty(); });
    if (stop_) return;
    const MapInput input = std::move(inbox_.front());
    inbox_.pop_front();
    lock.unlock();
    try {
      Done done{Map(input), mapper_->map()};
      lock.lock();
      done_.push_back(std::move(done));
    } catch (...) {
      lock.lock();
      error_ = std::current_exception();
      stop_ = true;
    }
    done_ready_.notify_one();
  }
}

}  // namespace trav::scenarios
