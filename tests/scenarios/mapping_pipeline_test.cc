// MappingPipeline: frames are mapped in order and each map takes effect at its ready time, with
// or without the worker thread (the closed loop's identity test is in navigation_test.cc).
#include "scenarios/run/mapping_pipeline.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace trav::scenarios {
namespace {

// A mapper whose map is one cell holding the sum of the frames' scan times so far; it throws on a
// frame scanned at a negative time.
class SummingMapper final : public mapping::TraversabilityMapper {
 public:
  SummingMapper()
      : map_(common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(1, 1), 1.0),
             {"sum"}) {
    map_.Layer("sum").setZero();
  }
  mapping::MapUpdateResult Update(const common::PointCloud& points_W,
                                  const Eigen::Isometry3d& /*X_WB*/, double t_s) override {
    if (t_s < 0.0) throw std::runtime_error("negative time");
    map_.Layer("sum")(0, 0) += static_cast<float>(t_s);
    mapping::MapUpdateResult result;
    result.input_points = static_cast<int>(points_W.size());
    return result;
  }
  const common::GridLayers& map() const override { return map_; }

 private:
  common::GridLayers map_;
};

MapInput Frame(double scan_s, double latency_s, int points) {
  MapInput input;
  input.scan_time_s = scan_s;
  input.ready_s = scan_s + latency_s;
  input.cloud_O.points = Eigen::Matrix3Xf::Zero(3, points);
  return input;
}

class MappingPipelineTest : public testing::TestWithParam<bool> {};

TEST_P(MappingPipelineTest, EachMapTakesEffectAtItsReadyTimeInOrder) {
  MappingPipeline pipeline(std::make_unique<SummingMapper>(), GetParam());
  EXPECT_EQ(pipeline.threaded(), GetParam());
  EXPECT_EQ(pipeline.map(), nullptr);
  pipeline.Submit(Frame(1.0, 0.5, 10));
  pipeline.Submit(Frame(2.0, 0.5, 20));
  pipeline.Submit(Frame(3.0, 0.5, 30));
  // nothing is due before 1.5 s, whatever the worker has done meanwhile
  EXPECT_FALSE(pipeline.NextDue(1.49).has_value());
  EXPECT_EQ(pipeline.map(), nullptr);
  // at 2.6 s the first two are due, one call each, in order; each with its own map
  std::optional<MapUpdate> first = pipeline.NextDue(2.6);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->result.input_points, 10);
  EXPECT_EQ(pipeline.map()->Layer("sum")(0, 0), 1.0f);
  std::optional<MapUpdate> second = pipeline.NextDue(2.6);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->result.input_points, 20);
  EXPECT_EQ(pipeline.map()->Layer("sum")(0, 0), 3.0f);
  EXPECT_FALSE(pipeline.NextDue(2.6).has_value());
  EXPECT_EQ(pipeline.map()->Layer("sum")(0, 0), 3.0f);
  // exactly at its ready time
  std::optional<MapUpdate> third = pipeline.NextDue(3.5);
  ASSERT_TRUE(third.has_value());
  EXPECT_EQ(third->result.input_points, 30);
  EXPECT_EQ(pipeline.map()->Layer("sum")(0, 0), 6.0f);
  EXPECT_GE(third->mapping_ms, 0.0);
}

TEST_P(MappingPipelineTest, TheMappersErrorReachesTheLoopWhenItsFrameIsDue) {
  MappingPipeline pipeline(std::make_unique<SummingMapper>(), GetParam());
  pipeline.Submit(Frame(1.0, 0.1, 1));
  pipeline.Submit(Frame(-1.0, 2.2, 1));  // ready at 1.2 s
  ASSERT_TRUE(pipeline.NextDue(1.1).has_value());
  EXPECT_FALSE(pipeline.NextDue(1.15).has_value());
  EXPECT_THROW(pipeline.NextDue(1.2), std::runtime_error);
  EXPECT_EQ(pipeline.map()->Layer("sum")(0, 0), 1.0f);
}

TEST_P(MappingPipelineTest, FramesStillQueuedAtTheEndAreDropped) {
  // destroying the pipeline with frames queued or mapping must neither hang nor crash
  MappingPipeline pipeline(std::make_unique<SummingMapper>(), GetParam());
  for (int i = 0; i < 50; ++i) pipeline.Submit(Frame(0.1 * i, 0.1, 100));
  ASSERT_TRUE(pipeline.NextDue(0.1).has_value());
  EXPECT_EQ(pipeline.map()->Layer("sum")(0, 0), 0.0f);
}

std::string ThreadName(const testing::TestParamInfo<bool>& info) {
  return info.param ? "WorkerThread" : "Inline";
}
INSTANTIATE_TEST_SUITE_P(Threads, MappingPipelineTest, testing::Bool(), ThreadName);

}  // namespace
}  // namespace trav::scenarios
