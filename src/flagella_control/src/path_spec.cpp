#include "flagella_control/path_spec.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/strict_yaml.h"
#include "flagella_sim/core/text_lists.h"

namespace flagella::control {
namespace {

[[noreturn]] void fail(const std::string& message) { throw InputFileError("path: " + message); }

double positiveLength(const YAML::Node& node, const std::string& field) {
  if (!node[field]) fail("'" + field + "' is required for this shape (a length in metres > 0)");
  double value = 0.0;
  try {
    value = node[field].as<double>();
  } catch (const YAML::Exception&) {
    fail("'" + field + "' must be a number (metres > 0)");
  }
  if (!(value > 0.0) || !std::isfinite(value) || value > 1000.0)
    fail("'" + field + "' = " + std::to_string(value) + " is out of range (0, 1000] m");
  return value;
}

/// The text of a scalar field; a list or map there is an error naming the field.
std::string text(const YAML::Node& node, const std::string& field) {
  if (!node[field].IsScalar()) fail("'" + field + "' must be a single value, not a list or map");
  return node[field].Scalar();
}

bool turnsLeft(const YAML::Node& node) {
  if (!node["turn"]) return true;
  const std::string turn = text(node, "turn");
  if (turn == "left") return true;
  if (turn == "right") return false;
  fail("'turn' must be 'left' or 'right', got '" + abbreviated(turn) + "'");
}

std::string format(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void rejectUnknownKeys(const YAML::Node& node, const std::set<std::string>& allowed) {
  for (const auto& item : node) {
    if (!item.first.IsScalar()) fail("the keys of 'path' must be plain names");
    const std::string key = item.first.Scalar();
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail("unknown field '" + abbreviated(key) + "' (allowed: " + list + ")");
    }
  }
}

/// The frame named by the 'frame' field's text.
PathFrame pathFrame(const std::string& frame) {
  if (frame == "start") return PathFrame::Start;
  if (frame == "world") return PathFrame::World;
  fail("'frame' must be 'start' or 'world', got '" + abbreviated(frame) + "'");
}

/// The polyline's 'points', each a finite [x, y] pair in metres.
std::vector<Vec2> polylinePoints(const YAML::Node& node) {
  if (!node["points"] || !node["points"].IsSequence())
    fail("'points' is required for a polyline: a list of [x, y] pairs in metres");
  std::vector<Vec2> points;
  for (size_t i = 0; i < node["points"].size(); ++i) {
    const YAML::Node p = node["points"][i];
    if (!p.IsSequence() || p.size() != 2)
      fail("points[" + std::to_string(i) + "] must be a pair [x, y] in metres");
    double x = 0.0, y = 0.0;
    try {
      x = p[0].as<double>();
      y = p[1].as<double>();
    } catch (const YAML::Exception&) {
      fail("points[" + std::to_string(i) + "] must hold two numbers");
    }
    if (!std::isfinite(x) || !std::isfinite(y))
      fail("points[" + std::to_string(i) + "] must hold two finite numbers");
    points.emplace_back(x, y);
  }
  return points;
}

/// Sets spec's path and description from a polyline entry; returns whether it is closed.
bool readPolyline(const YAML::Node& node, PathSpec& spec) {
  const std::vector<Vec2> points = polylinePoints(node);
  bool closed = false;  // a polyline is open unless it says otherwise
  if (node["closed"]) {
    try {
      closed = node["closed"].as<bool>();
    } catch (const YAML::Exception&) {
      fail("'closed' must be true or false, got '" + abbreviated(text(node, "closed")) + "'");
    }
  }
  try {
    spec.path = Path::polyline(points, closed);
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
  spec.description = std::string(closed ? "closed " : "") + "polyline of " +
                     std::to_string(points.size()) + " points";
  return closed;
}

/// Sets spec's path and description from the 'shape' entry; returns whether the path is closed.
bool readShape(const YAML::Node& node, const std::string& shape, PathSpec& spec) {
  const bool left = turnsLeft(node);
  const double side_sign = left ? 1.0 : -1.0;
  const std::string turn_text = left ? "left" : "right";
  if (shape == "rectangle") {
    const double w = positiveLength(node, "width"), h = positiveLength(node, "height");
    spec.path = Path::polyline({{0, 0}, {w, 0}, {w, side_sign * h}, {0, side_sign * h}}, true);
    spec.description = "rectangle " + format(w) + " x " + format(h) + " m, turning " + turn_text;
  } else if (shape == "triangle") {
    const double a = positiveLength(node, "side");
    spec.path = Path::polyline({{0, 0}, {a, 0}, {a / 2, side_sign * a * std::sqrt(3.0) / 2}}, true);
    spec.description = "equilateral triangle, side " + format(a) + " m, turning " + turn_text;
  } else if (shape == "circle") {
    const double r = positiveLength(node, "radius");
    spec.path = Path::circle({0, 0}, 0.0, r, left);
    spec.description = "circle, radius " + format(r) + " m, turning " + turn_text;
  } else if (shape == "polyline") {
    return readPolyline(node, spec);
  } else {
    fail("unknown shape '" + abbreviated(shape) +
         "' (allowed: polyline, circle, rectangle, triangle)");
  }
  return true;
}

/// Reads the optional 'laps' field into spec.laps ([1, 100]; 1 for an open path).
void readLaps(const YAML::Node& node, bool closed, PathSpec& spec) {
  if (node["laps"]) {
    try {
      spec.laps = node["laps"].as<int>();
    } catch (const YAML::Exception&) {
      fail("'laps' must be a whole number in [1, 100], got '" + abbreviated(text(node, "laps")) +
           "'");
    }
    if (spec.laps < 1 || spec.laps > 100)
      fail("'laps' = " + std::to_string(spec.laps) + " is out of range [1, 100]");
    if (!closed && spec.laps != 1) fail("'laps' must be 1 for an open polyline");
  }
}

}  // namespace

PathSpec pathSpecFromYaml(const YAML::Node& node) {
  if (!node || !node.IsMap()) fail("the 'path' entry must be a map with a 'shape'");
  rejectUnknownKeys(node, {"shape", "frame", "width", "height", "side", "radius", "turn", "points",
                           "closed", "laps"});
  if (!node["shape"]) fail("'shape' is required: polyline, circle, rectangle or triangle");
  const std::string shape = text(node, "shape");
  PathSpec spec;
  const std::string frame = node["frame"] ? text(node, "frame") : "start";
  spec.frame = pathFrame(frame);

  const bool closed = readShape(node, shape, spec);
  readLaps(node, closed, spec);
  spec.description += frame == "start" ? " (start frame)" : " (world frame)";
  return spec;
}

PathSpec loadPathSpec(const std::string& file) {
  YAML::Node root;
  try {
    root = loadStrictYamlFile(file, "path");
  } catch (const YamlInputError& e) {
    throw InputFileError(e.what());  // this package's load errors are runtime errors
  }
  try {
    if (!root["path"]) fail("missing top-level 'path' entry");
    return pathSpecFromYaml(root["path"]);
  } catch (const YAML::Exception& e) {
    throw InputFileError(file + ": path: " + e.what());
  } catch (const std::runtime_error& e) {
    throw InputFileError(file + ": " + e.what());
  }
}

}  // namespace flagella::control
