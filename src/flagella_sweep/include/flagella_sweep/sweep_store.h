// A sweep's output folder: the plan (which sweep it holds), one record file per finished point
// (written atomically as the point ends, so a killed sweep loses no finished point and resumes
// with the missing ones), each point's work folder, and the result table built from the records
// in index order (the same table whatever backend ran the points, in whatever order).
//   OUT/plan.json  OUT/points/000007.json  OUT/work/000007/  OUT/results.csv  OUT/results.json
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flagella_sweep/sweep_spec.h"

namespace flagella::sweep {

class SweepStore {
 public:
  /// `out_dir` is made absolute (the points' tools run in the sweep file's folder).
  explicit SweepStore(const std::string& out_dir);

  /// Creates the folder and writes the plan, or checks that the plan already there is this
  /// sweep's (throws ConfigError naming both when OUT holds another sweep).
  void open(const SweepSpec& spec) const;
  const std::string& directory() const { return out_; }
  std::string workDirectory(int index) const;
  std::string recordPath(int index) const;
  bool hasRecord(int index) const;
  /// Indices in [0, count) without a record.
  std::vector<int> missing(int count) const;
  /// Writes a record atomically (temporary file, then rename).
  void writeRecord(const nlohmann::json& record) const;
  nlohmann::json readRecord(int index) const;

  /// Builds results.csv and results.json from the records present, rows in index order.
  /// Columns: index, the parameters, status, exit_code, error, wall_s, then every summary key
  /// (sorted). Returns the number of rows; `failed` gets the failed points' indices.
  int writeTable(const SweepSpec& spec, std::vector<int>& failed) const;

 private:
  std::string out_;
};

/// A JSON value as a CSV cell (strings quoted when needed, numbers as JSON prints them).
std::string csvCell(const nlohmann::json& value);

}  // namespace flagella::sweep
