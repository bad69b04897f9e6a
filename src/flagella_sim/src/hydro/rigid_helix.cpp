#include "flagella_sim/hydro/rigid_helix.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "flagella_sim/core/units.h"
#include "flagella_sim/hydro/rss_solver.h"

namespace flagella::rss {
namespace {

[[noreturn]] void fail(const std::string& field, const std::string& range, double value) {
  std::ostringstream msg;
  msg << field << " must be " << range << ", got " << value;
  throw std::invalid_argument(msg.str());
}

std::string str(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

void requirePositive(const std::string& field, double value) {
  if (!(std::isfinite(value) && value > 0.0)) fail(field, "finite and > 0", value);
}

}  // namespace

ResolvedHelix resolveHelix(const HelixSpec& in) {
  requirePositive("helix_radius", in.helix_radius);
  requirePositive("pitch", in.pitch);
  requirePositive("axial_length", in.axial_length);
  requirePositive("filament_radius", in.filament_radius);
  // A tube of radius a around the centreline does not cross the axis (a < R) and adjacent turns,
  // one pitch apart axially, do not overlap (2 a < lambda).
  if (!(in.filament_radius < in.helix_radius)) {
    fail("filament_radius", "< helix_radius = " + str(in.helix_radius), in.filament_radius);
  }
  if (!(2.0 * in.filament_radius < in.pitch)) {
    fail("filament_radius", "< pitch / 2 = " + str(0.5 * in.pitch), in.filament_radius);
  }
  if (in.handedness != 1 && in.handedness != -1) {
    fail("handedness", "+1 (right) or -1 (left)", in.handedness);
  }
  ResolvedHelix h;
  h.spec = in;
  h.spec.eps = in.eps.value_or(kSqrtE * in.filament_radius);  // docs/model.md 4.5
  requirePositive("eps", *h.spec.eps);
  h.spec.edge_length = in.edge_length.value_or(kDefaultEdgeLengthInRadii * in.filament_radius);
  const double edge = *h.spec.edge_length;
  requirePositive("edge_length", edge);
  const double turn = std::hypot(2.0 * units::pi * in.helix_radius, in.pitch);
  h.arc_length = in.axial_length / in.pitch * turn;  // docs/model.md 8.4.1
  if (!(edge < h.arc_length)) {
    fail("edge_length", "< helix arc length (" + str(h.arc_length) + ")", edge);
  }
  const double segments = std::ceil(h.arc_length / edge);
  if (segments + 1 > kMaxHelixNodes) {
    fail("edge_length",
         ">= arc length / " + std::to_string(kMaxHelixNodes - 1) + " (" +
             str(h.arc_length / (kMaxHelixNodes - 1)) + ") to keep the dense solve " + "within " +
             std::to_string(kMaxHelixNodes) + " nodes",
         edge);
  }
  h.node_count = static_cast<int>(segments) + 1;
  const double dphi = 2.0 * units::pi * in.axial_length / in.pitch / segments;
  // chord of a helix over dphi: sqrt((2 R sin(dphi/2))^2 + (lambda dphi / 2 pi)^2)
  h.actual_edge =
      std::hypot(2.0 * in.helix_radius * std::sin(0.5 * dphi), in.pitch * dphi / (2.0 * units::pi));
  return h;
}

Polyline helixNodes(const ResolvedHelix& h) {
  const HelixSpec& s = h.spec;
  const int segments = h.node_count - 1;
  const double phi_end = 2.0 * units::pi * s.axial_length / s.pitch;
  Polyline nodes(h.node_count);
  for (int p = 0; p < h.node_count; ++p) {
    const double phi = phi_end * p / segments;
    nodes[p] = Vec3(s.helix_radius * std::cos(phi), s.handedness * s.helix_radius * std::sin(phi),
                    s.pitch * phi / (2.0 * units::pi));
  }
  return nodes;
}

HelixResistance helixResistance(const HelixSpec& spec, double viscosity) {
  HelixResistance out;
  out.helix = resolveHelix(spec);
  out.viscosity = viscosity;
  const Polyline nodes = helixNodes(out.helix);
  const RssSolver solver(nodes, *out.helix.spec.eps, viscosity);
  const int m = solver.nodeCount();
  const Vec3 ez = Vec3::UnitZ();
  VecX u_trans(3 * m), u_rot(3 * m);
  for (int p = 0; p < m; ++p) {
    u_trans.segment<3>(3 * p) = ez;
    u_rot.segment<3>(3 * p) = ez.cross(nodes[p]);  // rigid rotation about the z axis
  }
  const VecX f_trans = solver.forceDensities(u_trans);
  const VecX f_rot = solver.forceDensities(u_rot);
  const VecX& l = solver.voronoiLengths();
  // Total force and torque on the fluid: sum of l_p f_p (docs/model.md 4.3 nodal forces).
  for (int p = 0; p < m; ++p) {
    const Vec3 ft = l[p] * f_trans.segment<3>(3 * p);
    const Vec3 fr = l[p] * f_rot.segment<3>(3 * p);
    out.A += ft.z();
    out.B += fr.z();
    out.B_reciprocal += nodes[p].cross(ft).z();
    out.D += nodes[p].cross(fr).z();
  }
  return out;
}

double HelixResistance::dimensionlessA() const { return A / (viscosity * helix.spec.helix_radius); }
double HelixResistance::dimensionlessB() const {
  return B / (viscosity * std::pow(helix.spec.helix_radius, 2));
}
double HelixResistance::dimensionlessD() const {
  return D / (viscosity * std::pow(helix.spec.helix_radius, 3));
}

}  // namespace flagella::rss
