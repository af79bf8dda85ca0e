/// \file param_table_impl.h
/// \brief ParamTable members that need MRPT's CConfigFile (kept out of the class body).
#pragma once

#include <mrpt/config/CConfigFile.h>

namespace dlo {

template <typename P>
P ParamTable<P>::loadFile(const std::string& path, const std::string& prefix,
                          const P& defaults) const {
  param_text::requireReadableConfig(path);
  try {
    // Inside the try: MRPT's parser throws its own exceptions for a malformed @define or ${...}.
    const mrpt::config::CConfigFile config(path);
    return load(config, prefix, defaults);
  } catch (const std::exception& e) {
    param_text::rethrowWithFile(path, e);
  }
}

}  // namespace dlo
