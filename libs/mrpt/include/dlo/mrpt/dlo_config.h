/// \file dlo_config.h
/// \brief dlo::DloParams <-> MRPT INI files: load, dump, and command-line overrides.
///
/// Each field of DloParams has exactly one INI key, named like the field, in the section named
/// like its group: [grid], [selection], [solver]. Missing keys keep their current value; every
/// loader validates the result and throws dlo::InputError with one sentence naming the key.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <string>
#include <vector>

#include "dlo/core/dlo_params.h"
#include "dlo/mrpt/param_table.h"

namespace dlo {

/// The INI table of DloParams, for composing larger parameter sets (see liftField()).
const std::vector<ParamField<DloParams>>& dloParamFields();

/// Name of the INI section of parameter group `group` ("grid", "selection", "solver"):
/// `group` itself when `prefix` is empty, else "prefix.group".
std::string dloSectionName(const std::string& prefix, const std::string& group);

/// Reads DloParams from `config`, starting from `defaults` (keys that are absent keep the default).
/// \param prefix section prefix, see dloSectionName(); empty for plain [grid], [selection],
///        [solver].
/// \throws InputError if a value does not parse, a key in one of the three sections is unknown,
///         or the result fails DloParams::validate().
DloParams loadDloParams(const mrpt::config::CConfigFileBase& config, const std::string& prefix = "",
                        const DloParams& defaults = DloParams());

/// Like loadDloParams() on the INI file `path`.
/// \throws InputError naming `path` if the file does not exist or cannot be read.
DloParams loadDloParamsFile(const std::string& path, const std::string& prefix = "",
                            const DloParams& defaults = DloParams());

/// Applies assignments "section.key=value" (as given to `--set`) in order, then validates.
/// \throws InputError naming the assignment if it is malformed, names an unknown section or key,
///         or its value does not parse; or with validate()'s sentence.
void applyDloParamOverrides(DloParams& params, const std::vector<std::string>& assignments);

/// Writes every parameter to `config` (sections as in loadDloParams()).
void saveDloParams(const DloParams& params, mrpt::config::CConfigFileBase& config,
                   const std::string& prefix = "");

/// All parameters as commented INI text, one comment line before each key; loadDloParams() of
/// this text gives back `params` exactly.
std::string dloParamsToIni(const DloParams& params, const std::string& prefix = "");

/// The text of config/dlo.ini: a header, then every key with its doc and default. The shipped
/// file is this text (a test compares them).
std::string dloConfigFileText();

}  // namespace dlo
