/// \file localizer_config.h
/// \brief dlo::LocalizerParams <-> MRPT INI: the [localizer] section that dlo-localize reads
/// beside dlo-slam's five sections.
#pragma once

#include <string>
#include <vector>

#include "dlo/mrpt/param_table.h"
#include "dlo/slam/localizer.h"

namespace dlo {

/// The INI table of LocalizerParams: section [localizer].
const ParamTable<LocalizerParams>& localizerParamTable();

/// Splits "section.key=value" overrides into those of [localizer] (`localizer`) and the others
/// (`slam`, for applySlamParamOverrides()), each in its order.
void splitLocalizerOverrides(const std::vector<std::string>& assignments,
                             std::vector<std::string>& slam, std::vector<std::string>& localizer);

/// LocalizerParams as dlo-localize resolves them: the defaults, then the [localizer] section of
/// the sensor profile `profile` (a built-in name or an INI file's path; empty: none; see
/// resolveSlamParams()), then that of the INI file `config_file` (if not empty; its other
/// sections are dlo-slam's and are not read here), then the "localizer.key=value" assignments of
/// `sets` (the others are skipped); every layer validated.
/// \throws InputError naming the file or the override, and the key.
LocalizerParams resolveLocalizerParams(const std::string& profile, const std::string& config_file,
                                       const std::vector<std::string>& sets);

/// The keys of [localizer] ("localizer.key") that the built-in sensor profiles set.
std::vector<std::string> localizerProfileKeys();

/// Commented INI text of `params` (the [localizer] section).
std::string localizerParamsToIni(const LocalizerParams& params);

/// The text of config/dlo-localize.ini: a header, then every [localizer] key with its doc and
/// default, the keys of the sensor profiles commented out. The shipped file is this text (a test
/// compares them).
std::string localizerConfigFileText();

}  // namespace dlo
