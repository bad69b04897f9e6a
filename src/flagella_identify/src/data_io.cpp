// Reading metadata files (dispatch on kind) and merging the data they name.
#include "flagella_identify/data_io.h"

#include <filesystem>
#include <utility>

#include "data_io_internal.h"
#include "flagella_sim/core/text_lists.h"
#include "metadata.h"

namespace flagella {
namespace identify {

double SteadyStateRow::sigmaOf(const std::string& output,
                               const std::map<std::string, double>& table_noise) const {
  if (const auto it = sigma.find(output); it != sigma.end()) return it->second;
  if (const auto it = table_noise.find(output); it != table_noise.end()) return it->second;
  return kMissing;
}

void append(MeasuredData& data, MeasuredData more) {
  for (SteadyStateTable& t : more.tables) data.tables.push_back(std::move(t));
  for (TimeSeries& s : more.series) data.series.push_back(std::move(s));
}

MeasuredData readMeasuredData(const std::string& metadata_yaml_path) {
  const data_io::Metadata meta = data_io::loadMetadata(metadata_yaml_path);
  const YAML::Node kind_node = meta.get("kind");
  if (!kind_node.IsDefined())
    meta.fail(meta.root(), "missing required key 'kind' (steady_state or time_series)");
  const std::string kind = meta.text(kind_node, "kind");
  MeasuredData data;
  if (kind == "steady_state")
    data.tables.push_back(data_io::readSteadyState(meta));
  else if (kind == "time_series")
    data.series.push_back(data_io::readSeries(meta));
  else
    meta.fail(kind_node,
              "kind: expected steady_state or time_series, got '" + abbreviated(kind) + "'");
  return data;
}

MeasuredData readMeasuredData(const std::vector<std::string>& metadata_yaml_paths) {
  MeasuredData data;
  for (const std::string& path : metadata_yaml_paths) append(data, readMeasuredData(path));
  return data;
}

std::string csvPathForMetadata(const std::string& yaml_path) {
  return std::filesystem::path(yaml_path).replace_extension(".csv").string();
}

}  // namespace identify
}  // namespace flagella
