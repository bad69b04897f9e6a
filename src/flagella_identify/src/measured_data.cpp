#include "flagella_identify/measured_data.h"

namespace flagella {
namespace identify {

const std::vector<std::string>& steadyOutputNames() {
  static const std::vector<std::string> names = {
      "v", "omega_h", "omega_t", "omega_yr", "R_yr", "buckling_threshold", "tilt"};
  return names;
}

}  // namespace identify
}  // namespace flagella
