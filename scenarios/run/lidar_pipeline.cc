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
  if (worker_thread) worker_ = std::thread([this] { Work(); });
}

LidarPipeline::~LidarPipeline() {
  if (!worker_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_one();
  worker_.join();
}

void LidarPipeline::Scan(const ScanStep& step) {
  const common::Stopwatch start;
  if (!step.movers_X_WI.empty()) scene_->SetMovingPoses(step.movers_X_WI);
  emulator_->Scan(*scene_, step.t_begin_s, step.t_end_s, step.X_WL);
  step_ms_.push_back(start.ElapsedMilliseconds());
}

bool LidarPipeline::Submit(ScanStep step) {
  TRAV_DEMAND(!frame_due_);
  const std::int64_t rays_before = emulator_->RaysBefore(step.t_end_s);
  const int per_frame = emulator_->rays_per_frame();
  frame_due_ = rays_before / per_frame > rays_submitted_ / per_frame;
  rays_submitted_ = std::max(rays_submitted_, rays_before);
  if (!threaded()) {
    Scan(step);
    return frame_due_;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    inbox_.push_back(std::move(step));
  }
  work_ready_.notify_one();
  return frame_due_;
}

void LidarPipeline::WaitIdle() {
  if (!threaded()) return;
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return (inbox_.empty() && !busy_) || error_ != nullptr; });
  if (error_ != nullptr) std::rethrow_exception(error_);
}

void LidarPipeline::TakeFrame(lidar::LidarFrame* frame) {
  TRAV_DEMAND(frame_due_);
  WaitIdle();
  emulator_->TakeFrame(frame);
  frame_due_ = false;
}

void LidarPipeline::TakeStepTimes(std::vector<double>* step_ms) {
  WaitIdle();
  step_ms->insert(step_ms->end(), step_ms_.begin(), step_ms_.end());
  step_ms_.clear();
}

void LidarPipeline::Work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_ready_.wait(lock, [this] { return stop_ || !inbox_.empty(); });
    if (stop_) return;
    ScanStep step = std::move(inbox_.front());
    inbox_.pop_front();
    busy_ = true;
    lock.unlock();
    try {
      // step_ms_ is the worker's while it is busy; the loop reads it only when the worker is idle
      Scan(step);
      lock.lock();
    } catch (...) {
      lock.lock();
      error_ = std::current_exception();
      stop_ = true;
    }
    busy_ = false;
    if (inbox_.empty() || error_ != nullptr) idle_.notify_one();
  }
}

}  // namespace trav::scenarios
