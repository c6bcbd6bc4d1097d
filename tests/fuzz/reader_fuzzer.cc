// Fuzzes the readers of data files: the first byte chooses the LiDAR scan table, the reference
// trajectory (track.file) or a Slurm tasks file (trav job-task); the rest is the file.
#include <cstdint>
#include <string>

#include "scenarios/experiments/job_array.h"
#include "scenarios/run/track_reference.h"
#include "sim/lidar/scan_pattern.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path = trav::fuzz::InputFile(data + 1, size - 1, "input");
  trav::fuzz::ExpectCleanRejection([&] {
    switch (data[0] % 3) {
      case 0:
        trav::lidar::TablePattern::Load(path);
        break;
      case 1: {
        trav::scenarios::TrackSettings settings;
        settings.reference = trav::scenarios::ReferenceShape::kFile;
        settings.file = path;
        trav::scenarios::BuildReference(settings, {});
        break;
      }
      default:
        trav::scenarios::ReadJobTask(path, data[0] / 3 % 4, "/usr/bin/trav");
        break;
    }
  });
  return 0;
}
