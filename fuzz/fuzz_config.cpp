// libFuzzer target: the bytes are a robot/simulation config YAML file, read as flagella_run
// reads it (loadConfigTree, parseSimulationConfig). Leading lines "--set section.field=value"
// are taken off the file and applied as command-line overrides.
#include <cstdint>
#include <string>
#include <vector>

#include "flagella_sim/simulation/simulation_config.h"
#include "fuzz_support.h"

namespace {

const std::string kSetPrefix = "--set ";

// Splits the leading "--set ..." lines off `text` (they are removed from it).
std::vector<std::string> takeOverrides(std::string& text) {
  std::vector<std::string> overrides;
  while (text.compare(0, kSetPrefix.size(), kSetPrefix) == 0) {
    const size_t end = text.find('\n');
    overrides.push_back(text.substr(
        kSetPrefix.size(), end == std::string::npos ? std::string::npos : end - kSetPrefix.size()));
    text.erase(0, end == std::string::npos ? text.size() : end + 1);
  }
  return overrides;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fuzz::ScratchDir dir;
  static const std::string path = dir.file("config.yaml");
  std::string text(reinterpret_cast<const char*>(data), size);
  const std::vector<std::string> overrides = takeOverrides(text);
  fuzz::writeFile(path, text);
  return fuzz::expectOnlyConfigErrors([&] {
    const YAML::Node tree = flagella::loadConfigTree(path, overrides);
    flagella::parseSimulationConfig(tree, path);
  });
}
