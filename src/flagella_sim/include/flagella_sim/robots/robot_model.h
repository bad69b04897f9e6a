// A configured robot (docs/model.md 8): its geometry as one typed value, and what the
// simulation, the tools and the summaries ask of a robot whatever its type. A robot type is a
// class deriving from RobotModelOf<its geometry>, a RobotDescriptor (robot_registry.h) and one
// line in src/robots/robot_list.def.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "flagella_sim/rod/network_builder.h"

namespace flagella {

/// One field of summary.json that describes the robot: an integer, a number or a text.
struct SummaryField {
  std::string key;
  std::variant<int, double, std::string> value;
};

class RobotModel {
 public:
  virtual ~RobotModel() = default;
  /// robot.type of the config (the descriptor's name).
  virtual const std::string& type() const = 0;
  /// The rod network, parts marked (docs/model.md 8).
  virtual RodNetwork build() const = 0;
  /// The tails' or the flagellum's material: its EI with filamentLength() scales the convergence
  /// test (docs/model.md 1.10); effects take their default density and radius from it.
  virtual const RodMaterial& filament() const = 0;
  /// L of the tails, L_t of a helix [m].
  virtual double filamentLength() const = 0;
  /// Number of tails (a helical flagellum counts one); a sweep without --n-tails sweeps this.
  virtual int tailCount() const = 0;
  /// How progress lines and summaries name the robot: "n = 2", "helical, 3.5 pitches".
  virtual std::string label() const = 0;
  /// The fields of summary.json that describe the robot, in their order.
  virtual std::vector<SummaryField> summaryFields() const = 0;
  /// The tilt of a helical flagellum against the head axis (docs/model.md 8.4.4), the
  /// summaries' buckling indicator; nullopt for robots without one (no buckling metrics).
  virtual std::optional<double> flagellumTilt(const VecX& /*q*/, const RobotParts& /*parts*/,
                                              const Vec3& /*head_axis*/) const {
    return std::nullopt;
  }
  /// True when flagellumTilt gives a value (decided by the type, not by the state).
  virtual bool hasFlagellumTilt() const { return false; }
  /// A copy (configs are edited copy-on-write, SimulationConfig::editRobotGeometry).
  virtual std::shared_ptr<RobotModel> clone() const = 0;
};

/// The base of a robot type whose geometry is `Geometry` (SimulationConfig::robotGeometry).
template <class Geometry>
class RobotModelOf : public RobotModel {
 public:
  explicit RobotModelOf(Geometry g) : geometry(std::move(g)) {}
  Geometry geometry;
};

}  // namespace flagella
