// The valid files the measured-data targets place beside their input: copies of shipped CSVs
// (steady-state tables and a time series) under their own names, so the metadata seeds that
// name them read them. FLAGELLA_SOURCE_ROOT is the repository (set by fuzz/CMakeLists.txt).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace fuzz {

/// Repository-relative paths of the CSVs copied into the scratch folder (by file name).
inline const char* const kFixedCsvs[] = {
    "test/data/readme_untethered_table.csv",  // steady state: omega_T_rpm, v, omega_h
    "test/data/readme_gimbal_threshold.csv",  // steady state: threshold only, override column
    "fuzz/seeds/design_table.csv",            // steady state: time_s, empty cells, quotes
    "fuzz/seeds/time_series.csv",             // time series with every column
};

/// Copies kFixedCsvs into `dir`; aborts if one is missing (the harness would be broken).
inline void copyFixedCsvs(const std::string& dir) {
  for (const char* relative : kFixedCsvs) {
    const std::filesystem::path from = std::filesystem::path(FLAGELLA_SOURCE_ROOT) / relative;
    std::error_code ec;
    std::filesystem::copy_file(from, std::filesystem::path(dir) / from.filename(),
                               std::filesystem::copy_options::overwrite_existing, ec);
    if (ec) {
      std::fprintf(stderr, "fuzz: cannot copy %s: %s\n", from.c_str(), ec.message().c_str());
      std::abort();
    }
  }
}

}  // namespace fuzz
