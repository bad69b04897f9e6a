// flagella_run robots: every registered robot type with its fields, as text or as markdown.
#include <cstdio>
#include <iostream>
#include <string>

#include "flagella_sim/robots/robot_registry.h"
#include "run_commands.h"

namespace flagella::cli {

int robotsCommand(bool markdown) {
  if (markdown) {
    std::cout << robotTableMarkdown(robotRegistry());
    return 0;
  }
  for (const RobotDescriptor* d : robotRegistry()) {
    std::printf("%s: %s\n", d->name.c_str(), d->description.c_str());
    for (const FieldSchema& f : robotSchema(*d))
      std::printf("  %-34s %s; default %s\n",
                  (f.field + (f.unit.empty() ? "" : " [" + f.unit + "]")).c_str(), f.range.c_str(),
                  f.fallback.empty() ? "none" : f.fallback.c_str());
  }
  return 0;
}

}  // namespace flagella::cli
