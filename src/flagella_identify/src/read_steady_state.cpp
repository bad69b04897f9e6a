// Reading a steady-state table: its metadata keys and the CSV of one row per experiment.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "data_io_internal.h"
#include "flagella_sim/core/text_lists.h"
#include "metadata.h"
#include "text_format.h"

namespace flagella {
namespace identify {
namespace data_io {

namespace {

/// The columns of a steady-state CSV by role (0-based indices, -1 if absent).
struct TableColumns {
  int id = -1;
  int time = -1;
  int omega = -1;
  std::vector<std::pair<int, const MeasuredColumn*>> measured;
  std::vector<std::pair<int, const MeasuredColumn*>> sigma;  ///< sigma_<measured column>
  std::vector<int> overrides;
};

/// The table's fields from the metadata keys (description, times, common overrides).
SteadyStateTable tableFromMetadata(const Metadata& meta) {
  meta.rejectUnknownKeys(
      meta.root(), "",
      {"kind", "csv", "description", "settle_time_s", "window_s", "overrides", "noise"});
  SteadyStateTable table;
  table.source = meta.file();
  if (meta.has("description"))
    table.description = meta.text(meta.get("description"), "description");
  table.settle_time =
      meta.has("settle_time_s")
          ? meta.inRange(meta.get("settle_time_s"), "settle_time_s", 0.0, false, kMaxTimeS, "s")
          : 10.0;
  table.window = meta.has("window_s")
                     ? meta.inRange(meta.get("window_s"), "window_s", 0.0, false, kMaxTimeS, "s")
                     : 20.0;
  table.overrides = meta.overrides();
  return table;
}

/// Sorts the header into roles; throws for an unknown column or a bad override name.
TableColumns classifyColumns(const csv::Table& csv) {
  TableColumns columns;
  for (size_t i = 0; i < csv.header.size(); ++i) {
    const std::string& name = csv.header[i];
    const int col = static_cast<int>(i);
    if (name == "id") {
      columns.id = col;
    } else if (name == "time_s") {
      columns.time = col;
    } else if (name == "omega_T_rpm") {
      columns.omega = col;
    } else if (const MeasuredColumn* m = measuredByColumn(name)) {
      columns.measured.emplace_back(col, m);
    } else if (const MeasuredColumn* u = sigmaColumnOf(name)) {
      columns.sigma.emplace_back(col, u);
    } else if (name.find('.') != std::string::npos) {
      const std::string problem = overrideNameProblem(name);
      if (!problem.empty())
        throw DataError(csv.path, csv.header_line, col + 1,
                        "override column '" + abbreviated(name) + "' " + problem);
      columns.overrides.push_back(col);
    } else {
      throw DataError(csv.path, csv.header_line, col + 1,
                      "unknown column '" + abbreviated(name) +
                          "' (allowed: id, time_s, omega_T_rpm, " +
                          joined(measuredColumnNames(), ", ") +
                          ", sigma_<measured column> (that column's uncertainty in each row)" +
                          ", or a config override 'section.field' with section one of " +
                          joined(overrideSections(), ", ") + ")");
    }
  }
  return columns;
}

/// True when the only measured column is the buckling threshold (no motor speed needed).
bool thresholdOnly(const TableColumns& columns) {
  for (const auto& [col, m] : columns.measured)
    if (std::string(m->output) != "buckling_threshold") return false;
  return !columns.measured.empty();
}

/// Throws unless the CSV has the motor speed (unless it measures only buckling thresholds), a
/// measured column, and noise for each one.
void checkColumns(const Metadata& meta, const csv::Table& csv, const TableColumns& columns,
                  const std::map<std::string, double>& noise) {
  if (columns.omega < 0 && !thresholdOnly(columns)) missingColumn(csv, "omega_T_rpm");
  if (columns.measured.empty())
    throw DataError(
        csv.path, csv.header_line, 1,
        "no measured column; expected at least one of " + joined(measuredColumnNames(), ", "));
  for (const auto& [col, u] : columns.sigma)
    if (std::none_of(columns.measured.begin(), columns.measured.end(),
                     [u = u](const auto& m) { return m.second == u; }))
      throw DataError(csv.path, csv.header_line, col + 1,
                      "column '" + csv.header[col] + "' gives the uncertainty of '" + u->column +
                          "', which the table does not have");
  // A measured column needs the metadata's noise unless every row may give its own (checked
  // per row in readSteadyState).
  for (const auto& [col, m] : columns.measured)
    if (std::none_of(columns.sigma.begin(), columns.sigma.end(),
                     [m = m](const auto& u) { return u.second == m; }))
      meta.requireNoise(noise, m->column,
                        "'" + csv.path + "' has the measured column '" + m->column + "'");
}

/// Throws unless each measured value of the row has an uncertainty (its own or the table's).
void checkRowUncertainty(const csv::Table& csv, const csv::Row& r, const TableColumns& columns,
                         const SteadyStateRow& row, const std::map<std::string, double>& noise) {
  for (const auto& [col, m] : columns.measured)
    if (std::isfinite(row.measured.at(m->output)) && !std::isfinite(row.sigmaOf(m->output, noise)))
      throw DataError(csv.path, r.line, col + 1,
                      std::string("'") + m->column +
                          "' has no uncertainty in this row: its sigma_" + m->column +
                          " cell is empty and the metadata has no 'noise." + m->column + "'");
}

/// One experiment from a CSV row, in SI units (the field count already checked).
SteadyStateRow readRow(const csv::Table& csv, const csv::Row& r, const TableColumns& columns) {
  SteadyStateRow row;
  row.line = r.line;
  if (columns.id >= 0) row.id = r.fields[columns.id];
  if (columns.time >= 0) {
    const std::optional<double> t = rangedNumber(csv, r, columns.time, true, 0.0, kMaxTimeS, "s");
    row.time = t ? *t : kMissing;
  }
  if (columns.omega >= 0)
    row.omega_T =
        *rangedNumber(csv, r, columns.omega, false, -kMaxRpm, kMaxRpm, "rpm") * kRadPerSecPerRpm;
  for (int col : columns.overrides)
    if (!r.fields[col].empty()) row.overrides.emplace_back(csv.header[col], r.fields[col]);
  for (const auto& [col, m] : columns.measured) {
    const std::optional<double> value = rangedNumber(csv, r, col, true, m->min, m->max, m->unit);
    row.measured[m->output] = value ? *value * m->to_si : kMissing;
  }
  // docs/model.md 7.6: a row's own uncertainty, in the unit of its column, > 0
  for (const auto& [col, m] : columns.sigma) {
    const std::optional<double> sigma =
        rangedNumber(csv, r, col, true, std::numeric_limits<double>::min(), m->max, m->unit);
    if (sigma) row.sigma[m->output] = *sigma * m->to_si;
  }
  return row;
}

}  // namespace

SteadyStateTable readSteadyState(const Metadata& meta) {
  SteadyStateTable table = tableFromMetadata(meta);
  const std::map<std::string, double> noise = meta.noise(measuredColumnNames());
  const std::string csv_path = meta.filePath("csv");
  table.csv = csv_path;

  const csv::Table csv = csv::read(csv_path);
  indexHeader(csv);  // duplicate and empty names
  const TableColumns columns = classifyColumns(csv);
  checkColumns(meta, csv, columns, noise);
  for (const auto& [key, sigma] : noise) {
    const MeasuredColumn* m = measuredByColumn(key);
    table.noise[m->output] = sigma * m->to_si;
  }
  if (csv.rows.empty())
    throw DataError(csv.path, csv.header_line, 1, "no data rows after the header");

  for (const csv::Row& r : csv.rows) {
    checkFieldCount(csv, r);
    table.rows.push_back(readRow(csv, r, columns));
    checkRowUncertainty(csv, r, columns, table.rows.back(), table.noise);
  }
  return table;
}

}  // namespace data_io
}  // namespace identify
}  // namespace flagella
