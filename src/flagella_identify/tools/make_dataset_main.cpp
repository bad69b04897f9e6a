// flagella_make_dataset: writes a measured-style data set (YAML metadata + CSV) generated from
// a truth model with a hidden effect, as the tests do; for examples and for trying the tool.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/model.h"
#include "flagella_sim/runtime/tool_main.h"

using namespace flagella;
using namespace flagella::identify;

int main(int argc, char** argv) {
  CLI::App app{"flagella_make_dataset: a measured-style data set with a hidden effect"};
  std::string case_name, out,
      config = FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
  int seed = 1;
  std::string names;
  for (const DiscoveryCase& c : discoveryCases()) names += (names.empty() ? "" : ", ") + c.name;
  app.add_option("--case", case_name, "hidden-effect case: " + names)->required();
  app.add_option("--seed", seed, "draws the truth and the noise")->capture_default_str();
  app.add_option("--config", config, "baseline robot config")->capture_default_str();
  // checked before the truth is simulated (minutes for some cases), not when writing
  const CLI::Validator in_existing_directory(
      [](const std::string& path) -> std::string {
        const std::filesystem::path directory = std::filesystem::path(path).parent_path();
        if (directory.empty() || std::filesystem::is_directory(directory)) return "";
        return "its directory '" + directory.string() + "' does not exist";
      },
      "FILE in an existing directory");
  app.add_option("--out", out, "metadata YAML to write (the CSV goes next to it)")
      ->required()
      ->check(in_existing_directory);
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] {
    const YAML::Node baseline = loadConfigTree(config, {});
    const GeneratedCase g = generateCase(discoveryCaseByName(case_name), baseline, config, seed);
    // The data must not give the hidden truth away: it is printed, not stored.
    const std::string description =
        "measured-style data generated from a truth model (flagella_make_dataset, seed " +
        std::to_string(seed) + ")";
    if (!g.data.tables.empty()) {
      SteadyStateTable t = g.data.tables.front();
      t.description = description;
      writeSteadyStateTable(t, out);
    } else {
      TimeSeries s = g.data.series.front();
      s.description = description;
      writeTimeSeries(s, out);
    }
    std::cout << "wrote " << out << " and " << csvPathForMetadata(out)
              << "\ntruth: " << g.description << "\n";
    return 0;
  });
}
