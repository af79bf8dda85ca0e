// Fuzz target: INI parameter files as the programs read them, through MRPT's config parser
// (CConfigFile: sections, keys, comments, @define, ${...}) and DLO's parameter tables:
// loadDloParamsFile ([grid] [selection] [solver]; dlo-register, CDirectHeightAligner) and
// loadSlamParamsFile (plus [odometry] and [loop]; dlo-slam). Each line is also tried as a
// `--set section.key=value` override. A bad file must throw InputError naming it; accepted
// parameters must survive the documented round trip through the dumped INI text exactly.
#include <mrpt/config/CConfigFileMemory.h>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "allocation_limit.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/dlo_config.h"
#include "dlo/slam/slam_config.h"
#include "fuzz_input_file.h"

namespace {

/// Every parameter of `p`, in table order.
template <typename P>
std::vector<double> values(const std::vector<dlo::ParamField<P>>& fields, const P& p) {
  std::vector<double> out;
  for (const auto& f : fields) out.push_back(f.get(p));
  return out;
}

/// Loads the file with `load_file`, applies `lines` as overrides with `apply`, and checks that
/// whatever is accepted reads back exactly (`load`) from the text `dump` makes of it.
template <typename P, typename LoadFile, typename Load, typename Apply, typename Dump>
void exercise(const std::vector<dlo::ParamField<P>>& fields, LoadFile load_file, Load load,
              Apply apply, Dump dump, const std::string& path,
              const std::vector<std::string>& lines) {
  auto requireRoundTrip = [&](const P& p) {
    const mrpt::config::CConfigFileMemory dumped(dump(p));
    if (values(fields, load(dumped)) != values(fields, p)) __builtin_trap();
  };
  try {
    requireRoundTrip(load_file(path));
  } catch (const dlo::InputError& e) {
    dlo::fuzz::requireNames(e.what(), path);
  }
  try {
    P p;
    apply(p, lines);
    requireRoundTrip(p);
  } catch (const dlo::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dlo::fuzz::withHeapBudget([&] {
    static dlo::fuzz::FuzzInputFile file;
    const std::string& path = file.write(data, size);
    std::vector<std::string> lines;
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    for (std::string line; std::getline(in, line);) lines.push_back(line);

    exercise(
        dlo::dloParamFields(), [](const std::string& f) { return dlo::loadDloParamsFile(f); },
        [](const mrpt::config::CConfigFileBase& c) { return dlo::loadDloParams(c); },
        dlo::applyDloParamOverrides, [](const dlo::DloParams& p) { return dlo::dloParamsToIni(p); },
        path, lines);
    const auto& slam = dlo::slamParamTable();
    exercise(
        slam.fields(), [](const std::string& f) { return dlo::loadSlamParamsFile(f); },
        [&](const mrpt::config::CConfigFileBase& c) { return slam.load(c, "", dlo::SlamParams()); },
        dlo::applySlamParamOverrides, dlo::slamParamsToIni, path, lines);
  });
  return 0;
}
