#pragma once

#include <cstddef>
#include <string>

namespace trav::common {

/// The largest input file trav reads whole (scenario, batch, tuning, scan table, track, job and
/// collect files) [bytes].
inline constexpr std::size_t kMaxInputFileBytes = 64u << 20;

/// Checks that `path` names a regular file (not a folder, FIFO or device, which could block or
/// never end) of at most `max_bytes`. @throws InputError naming the file and `what` it is for
/// ("scan table") otherwise.
void RequireRegularFile(const std::string& path, const std::string& what,
                        std::size_t max_bytes = kMaxInputFileBytes);

/// The contents of the regular file `path` (RequireRegularFile). @throws InputError naming the
/// file and `what` it is for if it is not one or cannot be read.
std::string ReadInputFile(const std::string& path, const std::string& what,
                          std::size_t max_bytes = kMaxInputFileBytes);

}  // namespace trav::common
