#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/enum_names.h"

namespace trav::renders {

/// What the ground looks like in videos.
enum class GroundMaterial {
  kGrass,  ///< green, soil on steep slopes, rock on the steepest
  kSoil,   ///< rubble: brown soil, rock on steep slopes
  kRock,   ///< bare grey stone
  kFloor,  ///< an indoor floor: light tiles with 1 m joints
};

/// The names of GroundMaterial's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<GroundMaterial>, 4> kGroundMaterialNames{
    {{GroundMaterial::kGrass, "grass"},
     {GroundMaterial::kSoil, "soil"},
     {GroundMaterial::kRock, "rock"},
     {GroundMaterial::kFloor, "floor"}}};
constexpr const auto& EnumNames(GroundMaterial) { return kGroundMaterialNames; }

/// A colour texture for a height field: each texel coloured by `material`, brightened with height,
/// turning to soil and rock with the local slope, with a fixed fine and coarse grain (a hash of
/// the texel, so the same ground always looks the same).
/// `height_m` holds the heights [m] at (num_x, num_y) >= 2 x 2 samples evenly spaced over an area
/// of `extent_m` (x, y) [m], the first and last at its edges; the result is `size` x `size` RGB
/// texels, row r covering the band [r, r + 1) / size of the area along +y (row 0 at the low-y
/// edge), column c the band along +x.
std::vector<std::uint8_t> GroundTexture(const Eigen::MatrixXf& height_m,
                                        const Eigen::Vector2d& extent_m, GroundMaterial material,
                                        int size);

}  // namespace trav::renders
