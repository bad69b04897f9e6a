// libFuzzer target: the bytes are a dataset metadata YAML file, read by readMeasuredData in a
// folder that also holds valid steady-state tables and a time series it may name (fixed_data.h).
#include <cstdint>

#include "fixed_data.h"
#include "flagella_identify/data_io.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fuzz::ScratchDir dir;
  static const std::string path = [] {
    fuzz::copyFixedCsvs(dir.path());
    return dir.file("metadata.yaml");
  }();
  fuzz::writeFile(path, data, size);
  return fuzz::expectOnlyConfigErrors([&] { flagella::identify::readMeasuredData(path); });
}
