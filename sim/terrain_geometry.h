#pragma once

#include <vector>

#include "common/point_cloud.h"
#include "sim/terrain.h"

namespace trav::sim {

/// The ground as triangles, two per height-field cell (for ray casting and export).
TriangleMesh GroundMesh(const TerrainWorld& world);

/// The obstacle primitives as triangles: boxes exactly; cylinders, capsules and spheres as surfaces
/// of revolution with `segments` around (>= 3).
TriangleMesh ObstacleMesh(const std::vector<Obstacle>& obstacles, int segments = 16);

/// Appends `mesh` to `into`.
void AppendMesh(const TriangleMesh& mesh, TriangleMesh* into);

/// Points on the surface of `mesh` in W, on a barycentric lattice of every triangle with at most
/// `spacing_m` between neighbours.
common::PointCloud SampleSurface(const TriangleMesh& mesh, double spacing_m);

/// A dense noise-free point cloud of the world in W: the ground at every height sample and the
/// obstacle surfaces sampled every `spacing_m` or closer (parts below the ground are dropped).
/// Used for ground truth and export.
common::PointCloud DenseCloud(const TerrainWorld& world, double spacing_m);

}  // namespace trav::sim
