/// \file slam_config.h
/// \brief dlo::SlamParams <-> MRPT INI: sections [grid] [selection] [solver] (registration),
/// [odometry] and [loop].
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <string>
#include <vector>

#include "dlo/mrpt/param_table.h"
#include "dlo/slam/slam_params.h"

namespace dlo {

/// The INI table of SlamParams: DloParams' keys followed by [odometry] and [loop].
const ParamTable<SlamParams>& slamParamTable();

/// Reads SlamParams from the INI file `path` (missing keys keep `defaults`).
/// \throws InputError naming the file and the key.
SlamParams loadSlamParamsFile(const std::string& path, const SlamParams& defaults = SlamParams());

/// Applies "section.key=value" overrides (any of the five sections), then validates.
void applySlamParamOverrides(SlamParams& params, const std::vector<std::string>& assignments);

/// Commented INI text of all parameters.
std::string slamParamsToIni(const SlamParams& params);

/// The keys ("section.key") that the built-in sensor profiles set.
std::vector<std::string> sensorProfileKeys();

/// The text of config/dlo-slam.ini: a header, then every key with its doc and default, the
/// keys of the sensor profiles commented out. The shipped file is this text (a test compares
/// them).
std::string slamConfigFileText();

/// docs/parameters.md: every key of every section with its default (and each profile's
/// value where a sensor profile sets it) and its doc, from the same table.
std::string parameterReferenceMarkdown();

}  // namespace dlo
