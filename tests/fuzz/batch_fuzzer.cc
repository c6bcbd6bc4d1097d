// Fuzzes the batch and tuning file loaders: the first byte chooses which, the rest is the file.
// Scenario files they name resolve against the scratch folder, where the seeds' scenarios are.
#include <cstdint>
#include <string>

#include "scenarios/experiments/batch.h"
#include "scenarios/experiments/tuning.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool tune = (data[0] & 1) != 0;
  const std::string path = trav::fuzz::InputFile(data + 1, size - 1, tune ? "t.yaml" : "b.yaml");
  trav::fuzz::InputFile(reinterpret_cast<const std::uint8_t*>(
                            "schema_version: 1\nname: s\nmode: drive\nduration: 1\n"),
                        49, "s.yaml");
  trav::fuzz::ExpectCleanRejection([&] {
    if (tune) {
      trav::scenarios::LoadTuneFile(path);
    } else {
      trav::scenarios::ExpandBatch(trav::scenarios::LoadBatchFile(path));
    }
  });
  return 0;
}
