// The strictness every reader of a YAML map shares (the configs' FieldReader, the controller
// files' MapReader, the identification metadata): which keys were asked for, and the first key
// nothing asked for. Each reader words its own errors; this is the one place that decides what
// counts as an unknown key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace flagella {

class StrictMap {
 public:
  /// `node` may be a map, null or absent (then it has no keys); `path` is its dotted name.
  StrictMap(YAML::Node node, std::string path) : node_(std::move(node)), path_(std::move(path)) {}

  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }
  bool isMap() const { return node_ && node_.IsMap(); }
  /// node[key] (undefined if absent or if the node is no map); the key counts as asked for.
  YAML::Node take(const std::string& key) const;
  /// The key counts as asked for (a known field not read now, e.g. tested for presence).
  void markKnown(const std::string& key) const { known_.insert(key); }
  /// True if the map holds `key` (any value, null included); does not mark it.
  bool contains(const std::string& key) const;
  /// The map's keys in file order (YAML::BadConversion for a key that is not a plain name).
  std::vector<std::string> keys() const;
  /// The keys asked for so far, sorted.
  std::vector<std::string> knownKeys() const { return {known_.begin(), known_.end()}; }
  /// The key node of the first entry, in file order, whose key is not a plain name or was never
  /// asked for; nullopt if there is none.
  std::optional<YAML::Node> firstUnknownKey() const;

 private:
  YAML::Node node_;
  std::string path_;
  mutable std::set<std::string> known_;
};

}  // namespace flagella
