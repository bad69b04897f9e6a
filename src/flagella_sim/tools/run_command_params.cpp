// flagella_run params: the named parameters of a config, with their values and ranges.
#include <cstdio>
#include <string>

#include "flagella_sim/simulation/simulation.h"
#include "run_commands.h"

namespace flagella::cli {

int paramsCommand(const CommonOptions& o) {
  const SimulationConfig c = loadSimulationConfig(o.config, o.overrides);
  Simulation sim(c);
  std::printf("%-45s %14s %14s %14s  %s\n", "parameter", "value", "min", "max", "unit");
  for (const std::string& name : sim.parameterNames()) {
    const ParameterSpec& p = sim.parameterSpec(name);
    std::printf("%-45s %14.6g %14.6g %14.6g  %s\n", name.c_str(), p.value, p.min, p.max,
                p.unit.c_str());
  }
  return 0;
}

}  // namespace flagella::cli
