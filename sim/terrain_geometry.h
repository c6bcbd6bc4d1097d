#pragma once

#include <vector>

#include "common/point_cloud.h"
#include "sim/terrain.h"

namespace trav::sim {

/// The ground as triangles in W, two per height-field cell (for ray casting and export).
TriangleMesh GroundMesh(const TerrainWorld& world);

/// The obstacle primitives as triangles in W (common::PrimitiveMesh of each).
TriangleMesh ObstacleMesh(const std::vector<Obstacle>& obstacles, int segments = 16);

/// A dense noise-free point cloud of the world in W: the ground at every height sample and the
/// obstacle surfaces sampled every `spacing_m` or closer (parts below the ground are dropped).
/// Used for ground truth and export.
common::PointCloud DenseCloud(const TerrainWorld& world, double spacing_m);

}  // namespace trav::sim
