#include "scenarios/run/lidar_pipeline.h"

#include <algorithm>
#include <utility>

#include "common/check.h"
#include "common/stopwatch.h"

namespace trav::scenarios {

LidarPipeline::LidarPipeline(std::unique_ptr<lidar::RayScene> scene,
                             std::unique_ptr<lidar::LidarEmulator> emulator, bool worker_thread)
    : scene_(std::move(scene)), emulator_(std::move(emulator)) {
  TRAV_DEMAND(scene_ != nullptr && emulator_ != nullptr);
  if (worker_thread) {
    worker_ = std::make_unique<common::SerialWorker<ScanStep, double>>(
        [this](ScanStep& step) { return Scan(step); });
  }
}

double LidarPipeline::Scan(const ScanStep& step) {
  const common::Stopwatch start;
  if (!step.movers_X_WI.empty()) scene_->SetMovingPoses(step.movers_X_WI);
  emulator_->Scan(*scene_, step.t_begin_s, step.t_end_s, step.X_WL);
  return start.ElapsedMilliseconds();
}

bool LidarPipeline::Submit(ScanStep step) {
  TRAV_DEMAND(!frame_due_);
  const std::int64_t rays_before = emulator_->RaysBefore(step.t_end_s);
  const int per_frame = emulator_->rays_per_frame();
  frame_due_ = rays_before / per_frame > rays_submitted_ / per_frame;
  rays_submitted_ = std::max(rays_submitted_, rays_before);
  if (threaded()) {
    worker_->Submit(std::move(step));
  } else {
    step_ms_.push_back(Scan(step));
  }
  return frame_due_;
}

void LidarPipeline::TakeFrame(lidar::LidarFrame* frame) {
  TRAV_DEMAND(frame_due_);
  if (threaded()) worker_->TakeAll(&step_ms_);
  emulator_->TakeFrame(frame);
  frame_due_ = false;
}

void LidarPipeline::TakeStepTimes(std::vector<double>* step_ms) {
  if (threaded()) worker_->TakeAll(&step_ms_);
  step_ms->insert(step_ms->end(), step_ms_.begin(), step_ms_.end());
  step_ms_.clear();
}

}  // namespace trav::scenarios
