// Fuzzes `trav batch --collect` and `trav eval --collect` on a crafted folder: the first byte
// chooses which; the rest is its batch.json or options.json. Reports are written with no gnuplot on
// the PATH (plots are not what is fuzzed, and labels reach gnuplot only as quoted data).
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "scenarios/experiments/batch.h"
#include "scenarios/experiments/evaluation.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  setenv("PATH", "/nonexistent", 1);
  const bool eval = (data[0] & 1) != 0;
  const std::filesystem::path folder = trav::fuzz::ScratchFolder() / "campaign";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  trav::fuzz::InputFile(data + 1, size - 1, eval ? "campaign/options.json" : "campaign/batch.json");
  trav::fuzz::ExpectCleanRejection([&] {
    if (eval) {
      trav::scenarios::CollectEvaluation(folder.string());
    } else {
      trav::scenarios::CollectBatch(folder.string());
    }
  });
  return 0;
}
