// libFuzzer target: the bytes are a measured-data CSV, read by readMeasuredData through fixed
// valid metadata. The first byte picks the kind: even a steady-state table, odd a time series.
#include <cstdint>
#include <string>

#include "flagella_identify/data_io.h"
#include "fuzz_support.h"

namespace {

// Noise for every measured column, so that any header the fuzzer writes can be read.
const char* const kTableMetadata = R"(kind: steady_state
csv: input.csv
settle_time_s: 10
window_s: 20
noise: {v_mm_s: 0.01, omega_h_rpm: 0.1, omega_t_rpm: 0.1, omega_yr_rad_s: 0.01, R_yr_mm: 1,
        buckling_threshold_rpm: 0.1}
)";

const char* const kSeriesMetadata = R"(kind: time_series
csv: input.csv
noise: {position_mm: 0.5, orientation_rad: 0.01, turns: 0.1}
)";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fuzz::ScratchDir dir;
  static const std::string table = dir.file("table.yaml");
  static const std::string series = dir.file("series.yaml");
  static const std::string csv = dir.file("input.csv");
  static const bool written =
      (fuzz::writeFile(table, kTableMetadata), fuzz::writeFile(series, kSeriesMetadata), true);
  (void)written;
  if (size == 0) return 0;
  fuzz::writeFile(csv, data + 1, size - 1);
  const std::string& metadata = data[0] % 2 == 0 ? table : series;
  return fuzz::expectOnlyConfigErrors([&] { flagella::identify::readMeasuredData(metadata); });
}
