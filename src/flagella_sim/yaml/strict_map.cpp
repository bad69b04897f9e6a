#include "flagella_sim/core/strict_map.h"

namespace flagella {

YAML::Node StrictMap::take(const std::string& key) const {
  known_.insert(key);
  if (!isMap()) return YAML::Node();
  return node_[key];
}

bool StrictMap::contains(const std::string& key) const {
  return isMap() && static_cast<bool>(node_[key]);
}

std::vector<std::string> StrictMap::keys() const {
  std::vector<std::string> out;
  if (!isMap()) return out;
  for (const auto& entry : node_) out.push_back(entry.first.as<std::string>());
  return out;
}

std::optional<YAML::Node> StrictMap::firstUnknownKey() const {
  if (!isMap()) return std::nullopt;
  for (const auto& entry : node_)
    if (!entry.first.IsScalar() || !known_.count(entry.first.Scalar())) return entry.first;
  return std::nullopt;
}

}  // namespace flagella
