// The sweep output folder (sweep_store.h).
#include "flagella_sweep/sweep_store.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include "flagella_sim/core/parameter_set.h"

namespace flagella::sweep {

namespace {

namespace fs = std::filesystem;

std::string indexName(int index) {
  std::ostringstream s;
  s << std::setw(6) << std::setfill('0') << index;
  return s.str();
}

nlohmann::json planOf(const SweepSpec& spec) {
  nlohmann::json plan;
  plan["tool"] = toolName(spec.tool);
  plan["config"] = (fs::path(spec.directory) / spec.config).lexically_normal().string();
  plan["args"] = spec.args;
  nlohmann::json points = nlohmann::json::array();
  for (const PointSettings& p : spec.points) {
    nlohmann::json settings = nlohmann::json::array();
    for (const auto& [field, value] : p) settings.push_back({field, value});
    points.push_back(settings);
  }
  plan["points"] = points;
  return plan;
}

void writeAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  fs::rename(tmp, path);
}

}  // namespace

std::string csvCell(const nlohmann::json& value) {
  if (value.is_null()) return "";
  if (!value.is_string()) return value.dump();
  const std::string s = value.get<std::string>();
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void SweepStore::open(const SweepSpec& spec) const {
  fs::create_directories(fs::path(out_) / "points");
  fs::create_directories(fs::path(out_) / "work");
  const std::string plan_path = out_ + "/plan.json";
  const nlohmann::json plan = planOf(spec);
  if (fs::exists(plan_path)) {
    std::ifstream in(plan_path);
    nlohmann::json old;
    try {
      old = nlohmann::json::parse(in);
    } catch (const std::exception&) {
      throw ConfigError(plan_path + ": unreadable; remove the folder or choose another --out");
    }
    if (old != plan)
      throw ConfigError("--out " + out_ + " holds another sweep (its plan.json differs from " +
                        spec.file + "); choose another --out, or remove the folder to start over");
    return;
  }
  writeAtomically(plan_path, plan.dump(2) + "\n");
}

SweepStore::SweepStore(const std::string& out_dir)
    : out_(fs::absolute(out_dir).lexically_normal().string()) {}

std::string SweepStore::workDirectory(int index) const {
  return out_ + "/work/" + indexName(index);
}
std::string SweepStore::recordPath(int index) const {
  return out_ + "/points/" + indexName(index) + ".json";
}
bool SweepStore::hasRecord(int index) const { return fs::exists(recordPath(index)); }

std::vector<int> SweepStore::missing(int count) const {
  std::vector<int> out;
  for (int i = 0; i < count; ++i)
    if (!hasRecord(i)) out.push_back(i);
  return out;
}

void SweepStore::writeRecord(const nlohmann::json& record) const {
  writeAtomically(recordPath(record.at("index").get<int>()), record.dump(2) + "\n");
}

nlohmann::json SweepStore::readRecord(int index) const {
  std::ifstream in(recordPath(index));
  return nlohmann::json::parse(in);
}

int SweepStore::writeTable(const SweepSpec& spec, std::vector<int>& failed) const {
  std::vector<nlohmann::json> rows;
  std::set<std::string> summary_keys;
  failed.clear();
  for (int i = 0; i < static_cast<int>(spec.points.size()); ++i) {
    if (!hasRecord(i)) continue;
    nlohmann::json r = readRecord(i);
    for (auto it = r["summary"].begin(); it != r["summary"].end(); ++it)
      summary_keys.insert(it.key());
    if (r["status"] != "ok") failed.push_back(i);
    rows.push_back(std::move(r));
  }
  std::vector<std::string> columns = {"index"};
  columns.insert(columns.end(), spec.parameters.begin(), spec.parameters.end());
  for (const char* c : {"status", "exit_code", "error", "wall_s"}) columns.push_back(c);
  columns.insert(columns.end(), summary_keys.begin(), summary_keys.end());

  std::ostringstream csv;
  nlohmann::json table = nlohmann::json::array();
  for (std::size_t c = 0; c < columns.size(); ++c) csv << (c ? "," : "") << csvCell(columns[c]);
  csv << "\n";
  for (const nlohmann::json& r : rows) {
    nlohmann::json row = nlohmann::json::object();
    row["index"] = r["index"];
    for (const std::string& p : spec.parameters)
      row[p] = r["params"].contains(p) ? r["params"][p] : nlohmann::json();
    for (const char* c : {"status", "exit_code", "error", "wall_s"}) row[c] = r[c];
    for (const std::string& k : summary_keys)
      row[k] = r["summary"].contains(k) ? r["summary"][k] : nlohmann::json();
    for (std::size_t c = 0; c < columns.size(); ++c)
      csv << (c ? "," : "") << csvCell(row[columns[c]]);
    csv << "\n";
    table.push_back(std::move(row));
  }
  writeAtomically(out_ + "/results.csv", csv.str());
  writeAtomically(out_ + "/results.json", table.dump(2) + "\n");
  return static_cast<int>(rows.size());
}

}  // namespace flagella::sweep
