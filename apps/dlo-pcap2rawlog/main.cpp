// dlo-pcap2rawlog: converts a Velodyne .pcap capture into an MRPT rawlog of
// CObservationVelodyneScan.
#include <iostream>
#include <string>
#include <vector>

#include "dlo/mrpt/app_main.h"
#include "dlo/mrpt/input_error.h"
#include "dlo/mrpt/pcap_conversion.h"
#include "dlo/mrpt/progress_bar.h"

namespace {

constexpr const char* kUsage =
    R"(Usage: dlo-pcap2rawlog IN.pcap OUT.rawlog --model VLP16|HDL32|HDL64 [--quiet] [--help]

Converts a Velodyne packet capture into an MRPT rawlog, one rotation in memory at a time.

Output: OUT.rawlog (OUT.rawlog.gz is gzip-compressed), observation-only layout, one
CObservationVelodyneScan per full rotation (raw packets plus the model's default calibration,
sensorLabel "Velodyne_SCAN"); GPS packets set the timestamps but are not written. As with MRPT's
driver, the partial rotation after the last 360-degree wrap is not written; the first one may be
partial if the capture starts mid-turn. Written to OUT.tmp and renamed at the end, so an
existing OUT is never half-overwritten.

Options:
  --model M   sensor model: VLP16, HDL32 or HDL64 (required: a capture does not say).
  --quiet     no progress and no summary.
  --help      prints this text.

Exit status: 0 on success, 1 for a bad input, 2 for a command-line error; errors are one line
on stderr starting with "dlo-pcap2rawlog: ".
)";

using dlo::UsageError;

struct Arguments {
  std::string pcap;
  std::string out;
  std::string model;
  bool quiet = false;
  bool help = false;
};

Arguments parseArguments(int argc, char** argv) {
  Arguments a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      a.help = true;
      return a;
    }
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      positional.push_back(arg);
      continue;
    }
    // Both "--opt value" and "--opt=value".
    std::string value;
    const auto eq = arg.find('=');
    if (eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    } else if (arg == "--model") {
      if (i + 1 >= argc) throw UsageError{arg + " needs a value."};
      value = argv[++i];
    }
    if (arg == "--model") {
      a.model = value;
    } else if (arg == "--quiet") {
      a.quiet = true;
    } else {
      throw UsageError{"unknown option '" + arg + "' (see --help)."};
    }
  }
  if (positional.size() != 2) {
    throw UsageError{"expected IN.pcap and OUT.rawlog, got " + std::to_string(positional.size()) +
                     " arguments (see --help)."};
  }
  if (a.model.empty()) throw UsageError{"--model VLP16|HDL32|HDL64 is required."};
  a.pcap = positional[0];
  a.out = positional[1];
  return a;
}

int run(const Arguments& args) {
  dlo::VelodyneModel model;
  try {
    model = dlo::parseVelodyneModel(args.model);
  } catch (const dlo::InputError& e) {
    throw UsageError{std::string("--model: ") + e.what()};
  }
  dlo::ProgressBar bar(0, "scans", !args.quiet);
  const dlo::PcapConversionResult r = dlo::convertVelodynePcap(
      args.pcap, model, args.out, [&](size_t done, size_t) { bar.update(done); });
  bar.finish(r.scans);
  if (!args.quiet) {
    std::cout << "wrote " << r.scans << " scans (" << r.packets << " data packets) to '" << args.out
              << "'; " << r.gps_packets << " GPS packets seen.\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-pcap2rawlog", [&] {
    const Arguments args = parseArguments(argc, argv);
    if (args.help) {
      std::cout << kUsage;
      return 0;
    }
    return run(args);
  });
}
