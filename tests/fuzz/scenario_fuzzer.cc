// Fuzzes the scenario loader with --set overrides: the input is a scenario's YAML, then optionally
// a line "#--set" followed by one key.path=value per line.
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "common/yaml_reader.h"
#include "scenarios/run/scenario.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t marker = text.find("\n#--set\n");
  const std::string yaml = text.substr(0, marker);
  std::vector<std::string> sets;
  if (marker != std::string::npos) {
    std::istringstream lines(text.substr(marker + 8));
    for (std::string line; std::getline(lines, line);) sets.push_back(line);
  }
  trav::fuzz::ExpectCleanRejection([&] {
    trav::common::YamlDocument document = trav::common::YamlDocument::Parse(yaml, "fuzz.yaml");
    trav::scenarios::ApplyOverrides(sets, &document);
    const trav::scenarios::Scenario scenario = trav::scenarios::LoadScenario(document);
    // what a run writes first: the resolved scenario, and reads back on replay
    const std::string resolved = trav::scenarios::ResolvedScenarioYaml(scenario);
    trav::scenarios::LoadScenario(trav::common::YamlDocument::Parse(resolved, "resolved.yaml"));
  });
  return 0;
}
