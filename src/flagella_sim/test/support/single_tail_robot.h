// A robot type that lives in the test tree only (robot_registry.h): a head with one straight
// tail, registered at run time to show that a third robot type is its own files plus one
// registration, with nothing changed in the library.
#pragma once

#include "flagella_sim/robots/robot_registry.h"

namespace flagella::testing {

/// Its geometry, a type of its own (SimulationConfig::robotGeometry<SingleTailGeometry>()).
struct SingleTailGeometry {
  double tail_length = 0.05;  ///< [m]
  int tail_edges = 10;
  double head_radius = 0.01;  ///< [m]
  RodMaterial material;
};

/// Its descriptor: robot.type test_single_tail, fields tail_length, tail_edges, head_radius,
/// youngs_modulus. registerSingleTailRobot() registers it once (later calls do nothing).
const RobotDescriptor& singleTailRobotType();
void registerSingleTailRobot();

}  // namespace flagella::testing
