// The table of every effect a config can switch on (src/effects/effect_list.def), and what is
// built from it: effect construction, the known names, the Markdown table of the README.
#pragma once

#include <string>
#include <vector>

#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// Every registered effect, in the order of effect_list.def.
const std::vector<const EffectDescriptor*>& effectRegistry();
/// The descriptor of `name`, or nullptr.
const EffectDescriptor* findEffectDescriptor(const std::string& name);
/// The descriptor of `name`; throws ConfigError naming the known effects otherwise.
const EffectDescriptor& effectDescriptor(const std::string& name);
/// The registered names, in order.
std::vector<std::string> registeredEffectNames();
/// The registered names joined with ", " (for error messages).
std::string registeredEffectList();

/// Builds the effect `spec` names and sets its parameters; throws ConfigError naming the field
/// ("effects.<name>.<parameter>") and its range for a value out of range or an unknown name.
EffectPtr makeEffect(const EffectSpec& spec, const Medium& medium, const RobotDimensions& robot);

/// One Markdown table of every effect: options and parameters with units, defaults and ranges,
/// and whether model discovery tries it (README "Effects").
std::string effectTableMarkdown();

}  // namespace flagella
