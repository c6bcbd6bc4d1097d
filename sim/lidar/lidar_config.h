#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "common/archive.h"
#include "common/enum_names.h"

namespace trav::lidar {

/// Which scan pattern the emulated MID-360 fires (scan_pattern.h).
enum class PatternKind {
  kMid360,      ///< Livox's MID-360 scan table shipped in the tree (TablePattern::Mid360)
  kProcedural,  ///< the procedural model of it (ProceduralMid360Pattern)
};

/// The names of PatternKind's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<PatternKind>, 2> kPatternKindNames{
    {{PatternKind::kMid360, "mid360"}, {PatternKind::kProcedural, "procedural"}}};
constexpr const auto& EnumNames(PatternKind) { return kPatternKindNames; }

/// Settings of the emulated LiDAR (defaults: the Livox MID-360 datasheet).
struct LidarConfig {
  bool enabled{true};
  /// The pattern when no table is named: Livox's MID-360 table (default) or the procedural model.
  PatternKind pattern{PatternKind::kMid360};
  /// A scan table in Livox's CSV format (such as Livox's full MID-360 table); when set it is the
  /// pattern, whatever `pattern` says.
  std::string pattern_table;
  double points_per_second{200000.0};  ///< > 0
  double frame_period_s{0.1};          ///< one frame every 100 ms, > 0
  double range_min_m{0.1};             ///< blind zone: closer returns are dropped [m], >= 0
  double range_max_m{70.0};            ///< rays are cast this far [m], > range_min
  /// Detection: a surface of diffuse reflectance rho seen at incidence theta returns up to
  /// R = range_at_10_percent (rho c / 0.1)^k, c = max(cos(theta), incidence_floor), with k such
  /// that R is range_at_80_percent at rho c = 0.8 (datasheet: 40 m at 10 %, 70 m at 80 %); the
  /// chance of a return falls from 1 to 0 within about 5 % of R around it. Off: every surface
  /// returns up to range_max.
  bool detection{true};
  double range_at_10_percent_m{40.0};  ///< [m], > 0
  double range_at_80_percent_m{70.0};  ///< [m], >= range_at_10_percent
  /// The smallest cosine of incidence a surface presents: natural surfaces are rough below the
  /// mesh's scale (grass, gravel, asphalt's texture), so some facets face the sensor even when the
  /// mean surface is grazing. In [0, 1]; 0: ideal Lambertian planes.
  double incidence_floor{0.3};
  /// Relative standard deviation of the reported reflectivity, >= 0.
  double reflectivity_noise{0.05};
  double range_noise_m{0.02};  ///< standard deviation of the Gaussian range noise [m], >= 0
  double angular_noise_deg{
      0.1};             ///< standard deviation of the direction noise per axis [deg], >= 0
  double dropout{0.0};  ///< probability that a ray returns nothing, in [0, 1)
  /// Fraction of each frame's azimuth occluded (the paper occludes 15 % in its evaluation), in [0,
  /// 1): `occlusion_sectors` sectors of equal width at random azimuths, drawn anew per frame.
  double occlusion{0.0};
  int occlusion_sectors{3};
  std::uint64_t seed{1};  ///< noise, dropout and occlusion draws
  int threads{1};         ///< threads for casting large batches

  /// The keys of scenario section `lidar` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("enabled", &enabled);
    a->Enum("pattern", &pattern);
    a->Field("table", &pattern_table);
    a->Field("rate", &points_per_second, {1, 1000000.0});
    a->Field("frame_period", &frame_period_s, {0.005, 1});
    a->Field("range_min", &range_min_m, {0, 10});
    a->Field("range_max", &range_max_m, {0.1, 500});
    a->Field("detection", &detection);
    a->Field("range_at_10_percent", &range_at_10_percent_m, {0.1, 500});
    a->Field("range_at_80_percent", &range_at_80_percent_m, {0.1, 500});
    a->Field("incidence_floor", &incidence_floor, {0, 1});
    a->Field("reflectivity_noise", &reflectivity_noise, {0, 1});
    a->Field("range_noise", &range_noise_m, {0, 1});
    a->Field("angular_noise_deg", &angular_noise_deg, {0, 10});
    a->Field("dropout", &dropout, {0, 0.99});
    a->Field("occlusion", &occlusion, {0, 0.99});
    a->Field("occlusion_sectors", &occlusion_sectors, {1, 360});
    a->Field("seed", &seed);
    a->Field("threads", &threads, {1, 64});
  }
};

/// Checks the ranges of a LiDAR config. @throws common::InputError naming the key (relative:
/// "range_max") and value.
void ValidateLidarConfig(const LidarConfig& config);

}  // namespace trav::lidar
