#pragma once

#include <string>
#include <vector>

#include "scenarios/experiments/batch_report.h"

namespace trav::scenarios {

/// Side of a contact sheet's thumbnail [pixels].
constexpr int kThumbnailPixels = 200;

/// Writes the contact sheet of a batch's `results` into `out_dir` (each file atomically):
/// - contact_sheet.html: one cell per run in batch order, a grid of `runs/<id>/map_paths.png`
///   thumbnails (the world's final map with the plan and the driven path; "no image" where the
///   run has none) labelled with the run's id, swept parameters and outcome (green when the run
///   ended as its scenario expects, red otherwise), each linking to the run's video.mp4 when it
///   has one, else to its image, its summary or, for a run that failed to finish, its record
///   `failed/<id>.json`; a map that cannot be read counts as none;
/// - contact_sheet.png: the same thumbnails of the first 320 runs tiled (at most 8 a row), each in
///   a 4-pixel frame of its outcome's colour, grey where a run has no image; nothing when none of
///   them has one.
/// Returns the files written.
std::vector<std::string> WriteContactSheet(const std::string& out_dir,
                                           const std::vector<BatchResult>& results);

}  // namespace trav::scenarios
