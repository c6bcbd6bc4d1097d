#include "scenarios/run/terrain_files.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/io/vtk_lib_io.h>
#include <pcl/point_types.h>

#include "common/input_error.h"
#include "common/input_file.h"
#include "renders/image.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

constexpr char kKey[] = "terrain.parameters.file";
// The largest mesh read [triangles].
constexpr std::size_t kMaxTriangles = 10'000'000;
// The largest heightmap read [samples]: 4096 x 4096 (a 64 MB float32 file, common/input_file.h).
constexpr std::size_t kMaxSamples = 4096u * 4096u;

// `file` as a path: relative ones from the scenario file's folder.
fs::path Resolve(const std::string& scenario_source, const std::string& file) {
  const fs::path path(file);
  if (path.is_absolute() || scenario_source.empty() || scenario_source.front() == '<') {
    return fs::absolute(path).lexically_normal();
  }
  return fs::absolute(fs::path(scenario_source).parent_path() / path).lexically_normal();
}

// The extension of `path`, lower case.
std::string Extension(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// PNG rows run from the largest y down (MuJoCo's convention, as `trav terrain` writes them).
Eigen::MatrixXf ReadPngHeights(const std::string& path, const std::array<double, 2>& range_m) {
  common::RequireRegularFile(path, "heightmap");
  const renders::GrayImage16 image = renders::ReadPng16(path, kMaxSamples);
  Eigen::MatrixXf heights(image.width, image.height);
  const double scale = (range_m[1] - range_m[0]) / 65535.0;
  for (int row = 0; row < image.height; ++row) {
    for (int ix = 0; ix < image.width; ++ix) {
      heights(ix, image.height - 1 - row) =
          static_cast<float>(range_m[0] + scale * image.At(ix, row));
    }
  }
  return heights;
}

// float32, x fastest, rows along +y: Eigen's column-major (x, y) layout as it is. The bytes are
// taken in the machine's order, little-endian on every platform trav builds for.
Eigen::MatrixXf ReadRawHeights(const std::string& path, const Eigen::Vector2d& samples) {
  const auto num_x = static_cast<Eigen::Index>(samples.x());
  const auto num_y = static_cast<Eigen::Index>(samples.y());
  const std::string bytes = common::ReadInputFile(path, "heightmap", 4 * kMaxSamples);
  const std::size_t expected = static_cast<std::size_t>(num_x * num_y) * sizeof(float);
  if (bytes.size() != expected) {
    throw common::InputError(path, "",
                             "holds " + std::to_string(bytes.size()) + " bytes, not the " +
                                 std::to_string(expected) + " of " + std::to_string(num_x) + " x " +
                                 std::to_string(num_y) + " float32 samples");
  }
  Eigen::MatrixXf heights(num_x, num_y);
  std::memcpy(heights.data(), bytes.data(), expected);
  return heights;
}

}  // namespace

void LoadHeightmapFile(const std::string& scenario_source, sim::HeightmapParams* heightmap) {
  if (heightmap->file.empty()) {
    throw common::InputError(scenario_source, kKey, "is required for terrain type 'heightmap'");
  }
  const fs::path path = Resolve(scenario_source, heightmap->file);
  const std::string extension = Extension(path);
  const Eigen::Vector2d& samples = heightmap->samples;
  if (extension == ".raw" &&
      !(samples.x() >= 2.0 && samples.y() >= 2.0 && samples.x() == std::floor(samples.x()) &&
        samples.y() == std::floor(samples.y()))) {
    throw common::InputError(scenario_source, "terrain.parameters.samples",
                             "must give the .raw file's samples along x and y, whole numbers >= 2");
  }
  try {
    if (extension == ".png") {
      heightmap->heights_m = ReadPngHeights(path.string(), heightmap->height_range_m);
    } else if (extension == ".raw") {
      heightmap->heights_m = ReadRawHeights(path.string(), heightmap->samples);
    } else {
      throw common::InputError(common::QuotedExcerpt(heightmap->file) +
                               " must end in .png (16-bit grayscale) or .raw (float32)");
    }
  } catch (const common::InputError& e) {
    throw common::InputError(scenario_source, kKey, e.what());
  }
  heightmap->file = path.string();
}

void LoadGroundMeshFile(const std::string& scenario_source, sim::MeshGroundParams* mesh) {
  if (mesh->file.empty()) {
    throw common::InputError(scenario_source, kKey, "is required for terrain type 'mesh'");
  }
  const fs::path path = Resolve(scenario_source, mesh->file);
  const std::string extension = Extension(path);
  if (extension != ".obj" && extension != ".stl" && extension != ".ply") {
    throw common::InputError(scenario_source, kKey,
                             common::QuotedExcerpt(mesh->file) + " must end in .obj, .stl or .ply");
  }
  pcl::PolygonMesh polygons;
  try {
    common::RequireRegularFile(path.string(), "ground mesh", 16 * common::kMaxInputFileBytes);
  } catch (const common::InputError& e) {
    throw common::InputError(scenario_source, kKey, e.what());
  }
  pcl::io::loadPolygonFile(path.string(), polygons);
  pcl::PointCloud<pcl::PointXYZ> vertices;
  if (!polygons.cloud.data.empty()) pcl::fromPCLPointCloud2(polygons.cloud, vertices);
  common::TriangleMesh& triangles = mesh->mesh_W;
  triangles.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    triangles.vertices.col(static_cast<Eigen::Index>(i)) << vertices[i].x, vertices[i].y,
        vertices[i].z;
  }
  std::vector<Eigen::Vector3i> faces;
  for (const pcl::Vertices& polygon : polygons.polygons) {
    const pcl::Indices& v = polygon.vertices;
    const auto index_ok = [&](int i) {
      return i >= 0 && static_cast<std::size_t>(i) < vertices.size();
    };
    for (std::size_t k = 2; k < v.size(); ++k) {
      const bool valid = index_ok(v[0]) && index_ok(v[k - 1]) && index_ok(v[k]);
      if (!valid || faces.size() >= kMaxTriangles) {
        throw common::InputError(scenario_source, kKey,
                                 common::QuotedExcerpt(mesh->file) +
                                     (valid ? " has more than 10,000,000 triangles"
                                            : " has a face with a vertex index out of range"));
      }
      faces.emplace_back(v[0], v[k - 1], v[k]);
    }
  }
  if (faces.empty() || !triangles.vertices.allFinite()) {
    throw common::InputError(scenario_source, kKey,
                             common::QuotedExcerpt(mesh->file) +
                                 (faces.empty() ? " holds no triangle (not a readable mesh?)"
                                                : " has vertices that are not finite"));
  }
  triangles.triangles.resize(3, static_cast<Eigen::Index>(faces.size()));
  for (std::size_t t = 0; t < faces.size(); ++t) {
    triangles.triangles.col(static_cast<Eigen::Index>(t)) = faces[t];
  }
  mesh->file = path.string();
}

void LoadTerrainFiles(const std::string& scenario_source, sim::TerrainConfig* terrain) {
  if (terrain->type == sim::TerrainType::kHeightmap) {
    LoadHeightmapFile(scenario_source, &terrain->heightmap);
  } else if (terrain->type == sim::TerrainType::kMesh) {
    LoadGroundMeshFile(scenario_source, &terrain->mesh);
  }
}

}  // namespace trav::scenarios
