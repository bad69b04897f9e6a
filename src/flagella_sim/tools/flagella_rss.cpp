// flagella_rss: regularized Stokeslet segment (RSS) tools; `resistance` gives the axial
// resistance coefficients A, B, D of a rigid helix (docs/model.md 4).
#include <CLI/CLI.hpp>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "flagella_sim/hydro/rigid_helix.h"
#include "flagella_sim/runtime/tool_main.h"

namespace {

using flagella::rss::HelixResistance;
using flagella::rss::HelixSpec;

struct ResistanceOptions {
  HelixSpec spec;
  double eps = 0, edge_length = 0, viscosity = 1.0;
  std::string handedness = "right";
  std::string json;
};

// The library names fields as in HelixSpec; the user knows them as options.
std::string withOptionNames(std::string message) {
  static const std::map<std::string, std::string> kOptions = {
      {"helix_radius", "--helix-radius"},
      {"pitch", "--pitch"},
      {"axial_length", "--axial-length"},
      {"filament_radius", "--filament-radius"},
      {"eps", "--eps"},
      {"edge_length", "--edge-length"},
      {"viscosity", "--viscosity"}};
  const std::string field = message.substr(0, message.find(' '));
  const auto it = kOptions.find(field);
  if (it != kOptions.end()) message.replace(0, field.size(), it->second);
  return message;
}

std::string num(double x) {
  std::ostringstream out;
  out << std::setprecision(10) << x;
  return out.str();
}

void printReport(const HelixResistance& r, const std::string& handedness) {
  const HelixSpec& s = r.helix.spec;
  std::cout << "rigid helix (" << handedness << "-handed), regularized Stokeslet segments\n"
            << "  helix radius R      " << num(s.helix_radius) << " m\n"
            << "  pitch lambda        " << num(s.pitch) << " m\n"
            << "  axial length L      " << num(s.axial_length) << " m\n"
            << "  filament radius a   " << num(s.filament_radius) << " m\n"
            << "  eps                 " << num(*s.eps) << " m (" << num(*s.eps / s.filament_radius)
            << " a)\n"
            << "  edge length         " << num(r.helix.actual_edge) << " m (target "
            << num(*s.edge_length) << " m)\n"
            << "  nodes               " << r.helix.node_count << " (arc length "
            << num(r.helix.arc_length) << " m)\n"
            << "  viscosity mu        " << num(r.viscosity) << " Pa s\n"
            << "coefficients (loads on the fluid: F_z = A U + B Omega, T_z = B U + D Omega)\n"
            << "  A  drag    " << num(r.A) << " N s/m    A/(mu R)   = " << num(r.dimensionlessA())
            << "\n"
            << "  |B| thrust " << num(std::abs(r.B))
            << " N s      |B|/(mu R^2) = " << num(std::abs(r.dimensionlessB()))
            << "  (signed B = " << num(r.B) << "; reciprocal " << num(r.B_reciprocal) << ")\n"
            << "  D  torque  " << num(r.D) << " N m s    D/(mu R^3) = " << num(r.dimensionlessD())
            << "\n";
}

void writeJson(const HelixResistance& r, const std::string& handedness, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("--json: cannot write " + path);
  const HelixSpec& s = r.helix.spec;
  out << std::setprecision(17) << "{\n"
      << "  \"drag_coefficient\": " << r.dimensionlessA() << ",\n"
      << "  \"thrust_coefficient\": " << std::abs(r.dimensionlessB()) << ",\n"
      << "  \"torque_coefficient\": " << r.dimensionlessD() << ",\n"
      << "  \"A\": " << r.A << ",\n"
      << "  \"B_magnitude\": " << std::abs(r.B) << ",\n"
      << "  \"B_signed\": " << r.B << ",\n"
      << "  \"B_reciprocal\": " << r.B_reciprocal << ",\n"
      << "  \"D\": " << r.D << ",\n"
      << "  \"sign_convention\": \"loads on the fluid: F_z = A U + B Omega, T_z = B U + D Omega; "
         "B < 0 for a right-handed helix\",\n"
      << "  \"inputs\": {\n"
      << "    \"helix_radius\": " << s.helix_radius << ",\n"
      << "    \"pitch\": " << s.pitch << ",\n"
      << "    \"axial_length\": " << s.axial_length << ",\n"
      << "    \"filament_radius\": " << s.filament_radius << ",\n"
      << "    \"eps\": " << *s.eps << ",\n"
      << "    \"edge_length_target\": " << *s.edge_length << ",\n"
      << "    \"edge_length\": " << r.helix.actual_edge << ",\n"
      << "    \"node_count\": " << r.helix.node_count << ",\n"
      << "    \"viscosity\": " << r.viscosity << ",\n"
      << "    \"handedness\": \"" << handedness << "\"\n"
      << "  }\n}\n";
  if (!out) throw std::runtime_error("--json: cannot write " + path);
}

// Lengths are in metres; a robot of millimetres given in millimetres passes every range check
// (or fails on the node count without saying why), so lengths above a metre get a warning.
constexpr double kPlausibleLengthM = 1.0;

void warnImplausibleLengths(const ResistanceOptions& o) {
  const std::pair<const char*, double> lengths[] = {{"--helix-radius", o.spec.helix_radius},
                                                    {"--pitch", o.spec.pitch},
                                                    {"--axial-length", o.spec.axial_length},
                                                    {"--filament-radius", o.spec.filament_radius},
                                                    {"--eps", o.eps},
                                                    {"--edge-length", o.edge_length}};
  for (const auto& [option, value] : lengths)
    if (value > kPlausibleLengthM)
      std::cerr << "warning: " << option << " " << num(value)
                << " m is more than a metre: lengths are in metres (" << num(value)
                << " mm would be " << num(value * 1e-3) << ")\n";
}

int resistanceCommand(const ResistanceOptions& o) {
  warnImplausibleLengths(o);
  const HelixResistance r = flagella::rss::helixResistance(o.spec, o.viscosity);
  printReport(r, o.handedness);
  if (!o.json.empty()) {
    writeJson(r, o.handedness, o.json);
    std::cout << "wrote " << o.json << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"flagella_rss: regularized Stokeslet segments (RSS) hydrodynamics"};
  app.require_subcommand(1);

  ResistanceOptions o;
  CLI::App* res = app.add_subcommand(
      "resistance", "axial resistance coefficients A, B, D of a rigid helix (axis z)");
  res->add_option("--helix-radius", o.spec.helix_radius, "helix radius R [m], > 0")->required();
  res->add_option("--pitch", o.spec.pitch, "helix pitch lambda [m], > 2 a")->required();
  res->add_option("--axial-length", o.spec.axial_length, "axial length L [m], > 0")->required();
  res->add_option("--filament-radius", o.spec.filament_radius, "filament radius a [m], 0 < a < R")
      ->required();
  res->add_option("--eps", o.eps, "regularization eps [m], > 0 (default sqrt(e) a)");
  res->add_option("--edge-length", o.edge_length,
                  "target edge length [m], > 0 and < arc length (default 2 a)");
  res->add_option("--viscosity", o.viscosity, "dynamic viscosity mu [Pa s], > 0")
      ->capture_default_str();
  res->add_option("--handedness", o.handedness, "right | left")
      ->check(CLI::IsMember({"right", "left"}))
      ->capture_default_str();
  res->add_option("--json", o.json, "also write the results to this JSON file");

  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  try {
    if (res->count("--eps") > 0) o.spec.eps = o.eps;
    if (res->count("--edge-length") > 0) o.spec.edge_length = o.edge_length;
    o.spec.handedness = o.handedness == "left" ? -1 : 1;
    if (*res) return resistanceCommand(o);
  } catch (const std::invalid_argument& e) {
    std::cerr << "error: " << withOptionNames(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
