// flagella_run effects: every registered effect with its schema, as text or as markdown.
#include <cstdio>
#include <iostream>
#include <string>

#include "flagella_sim/effects/effect_registry.h"
#include "run_commands.h"

namespace flagella::cli {

int effectsCommand(bool markdown) {
  if (markdown) {
    std::cout << effectTableMarkdown();
    return 0;
  }
  for (const EffectDescriptor* d : effectRegistry()) {
    std::printf("%s: %s\n", d->name.c_str(), d->description.c_str());
    for (const EffectOption& o : d->options) {
      std::printf("  option    %-22s one of: %s (default %s)\n", o.name.c_str(),
                  o.choiceList().c_str(), o.fallback.c_str());
    }
    for (const ParameterSpec& p : d->parameters) {
      const std::string rule = d->defaultRule(p.name);
      std::printf("  parameter %-22s [%g, %g] %s, default %s: %s\n", p.name.c_str(), p.min, p.max,
                  p.unit.c_str(), rule.empty() ? std::to_string(p.value).c_str() : rule.c_str(),
                  p.description.c_str());
    }
    if (d->discovery)
      for (const FittableParameter& v : d->discovery->variables)
        std::printf("  discovery %-22s fitted in [%g, %g] %s%s\n", v.variable.c_str(), v.lower,
                    v.upper, v.unit.c_str(), v.log_scale ? " (log scale)" : "");
  }
  return 0;
}

}  // namespace flagella::cli
