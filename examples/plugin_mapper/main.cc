// A mapper of one's own in trav's closed loop: "height-span" scores each 0.2 m cell by the height
// span of the latest frame's points in it (0 m: cost 0; 0.3 m or more: cost 1), registered under
// that name and run on a scenario whose `mapping.method` names it. Prints the outcome and the
// mapper the summary names; OUT_DIR holds the run's files, run.mcap among them.
// Usage: plugin_mapper MODELS_DIR OUT_DIR
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "common/grid.h"
#include "common/yaml_reader.h"
#include "mapping/traversability_mapper.h"
#include "scenarios/run/plugins.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace {

namespace layers = trav::mapping::layers;

class HeightSpanMapper : public trav::mapping::TraversabilityMapper {
 public:
  HeightSpanMapper()
      : map_(trav::common::GridGeometry::Centered(Eigen::Vector2d::Zero(),
                                                  Eigen::Vector2d(30.0, 30.0), 0.2),
             {layers::kElevation, layers::kTraversability}) {}

  trav::mapping::MapUpdateResult Update(const trav::common::PointCloud& points_W,
                                        const Eigen::Isometry3d& X_WB, double /*t_s*/) override {
    map_.Recenter(X_WB.translation().head<2>());
    const trav::common::GridGeometry& g = map_.geometry();
    Eigen::MatrixXf low = Eigen::MatrixXf::Constant(g.num_x, g.num_y, INFINITY);
    Eigen::MatrixXf high = Eigen::MatrixXf::Constant(g.num_x, g.num_y, -INFINITY);
    for (Eigen::Index i = 0; i < points_W.size(); ++i) {
      const Eigen::Vector3f p = points_W.points.col(i);
      // only what the robot could touch: points up to 1 m above its base
      if (p.z() > X_WB.translation().z() + 1.0) continue;
      const std::optional<Eigen::Vector2i> cell = g.CellIndex(p.head<2>().cast<double>());
      if (!cell) continue;
      low(cell->x(), cell->y()) = std::min(low(cell->x(), cell->y()), p.z());
      high(cell->x(), cell->y()) = std::max(high(cell->x(), cell->y()), p.z());
    }
    trav::mapping::MapUpdateResult result;
    result.input_points = static_cast<int>(points_W.size());
    for (int iy = 0; iy < g.num_y; ++iy) {
      for (int ix = 0; ix < g.num_x; ++ix) {
        if (!std::isfinite(low(ix, iy))) continue;
        map_.Layer(layers::kElevation)(ix, iy) = high(ix, iy);
        map_.Layer(layers::kTraversability)(ix, iy) =
            std::min(1.0f, (high(ix, iy) - low(ix, iy)) / 0.3f);
        ++result.observed_cells;
      }
    }
    return result;
  }

  const trav::common::GridLayers& map() const override { return map_; }

 private:
  trav::common::GridLayers map_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: plugin_mapper MODELS_DIR OUT_DIR\n");
    return 2;
  }
  trav::scenarios::RegisterMapper("height-span", [](const trav::scenarios::Scenario&) {
    return std::make_unique<HeightSpanMapper>();
  });
  // flat ground with a wall across the way: the robot must map the wall to go round it
  const trav::scenarios::Scenario scenario =
      trav::scenarios::LoadScenario(trav::common::YamlDocument::Parse(R"(
schema_version: 1
mode: navigate
terrain:
  type: flat
  size: [24, 16]
  boxes: [{name: wall, centre: [0, 0], half_extents: [0.2, 3], height: 1.0}]
robot: {start: [-6, 0, 0]}
goal: [6, 0]
duration: 40
mapping: {method: height-span}
video: {enabled: false}
output: {mcap: true}
)",
                                                                      "plugin_mapper"));
  std::filesystem::create_directories(argv[2]);
  const trav::scenarios::RunSummary summary = trav::scenarios::RunScenario(
      scenario, trav::scenarios::RobotModelPath(scenario, argv[1]), argv[2]);
  std::printf("mapper %s: %s, %.1f m driven\n", summary.mapping->method.c_str(),
              trav::common::NameOf(summary.outcome), summary.distance_m);
  return summary.outcome == trav::scenarios::Outcome::kSuccess ? 0 : 1;
}
