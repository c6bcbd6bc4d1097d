#pragma once

#include <array>
#include <string>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/pose.h"
#include "common/trajectory.h"

namespace trav::scenarios {

/// Reference shapes of tracking scenarios.
enum class ReferenceShape { kLine, kCircle, kFigureEight, kSlalom, kFile };

/// The names of ReferenceShape's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<ReferenceShape>, 5> kReferenceShapeNames{
    {{ReferenceShape::kLine, "line"},
     {ReferenceShape::kCircle, "circle"},
     {ReferenceShape::kFigureEight, "figure_eight"},
     {ReferenceShape::kSlalom, "slalom"},
     {ReferenceShape::kFile, "file"}}};
constexpr const auto& EnumNames(ReferenceShape) { return kReferenceShapeNames; }

/// The reference of a tracking scenario (scenario key `track`).
struct TrackSettings {
  ReferenceShape reference{ReferenceShape::kFigureEight};
  /// Line and slalom: length [m]; circle: radius [m]; figure-eight: half its width [m]. > 0
  double size_m{3.0};
  double amplitude_m{1.0};        ///< slalom: lateral amplitude [m]
  double wavelength_m{6.0};       ///< slalom: distance between two left turns [m], > 0
  double speed_m_s{1.0};          ///< cruise speed [m/s], > 0
  double acceleration_m_s2{1.0};  ///< start and stop ramps [m/s^2], > 0
  /// kFile: CSV with header `t,x,y,yaw,v,omega` (W frame, times strictly increasing).
  std::string file;
  /// The keys of scenario section `track` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Enum("reference", &reference);
    a->Field("size", &size_m, {0.5, 1000.0});
    a->Field("amplitude", &amplitude_m, {0, 500});
    a->Field("wavelength", &wavelength_m, {0.5, 1000.0});
    a->Field("speed", &speed_m_s, {0.01, 10.0});
    a->Field("acceleration", &acceleration_m_s2, {0.01, 50.0});
    a->Field("file", &file);
  }
};

/// The reference trajectory: generated shapes start at `start_W` with their initial tangent along
/// its yaw; a file is used as it is (in W). @throws common::InputError for an unreadable or
/// malformed file.
common::Trajectory BuildReference(const TrackSettings& settings, const common::Pose2& start_W);

}  // namespace trav::scenarios
