// dlo-pcap2rawlog: converts a Velodyne .pcap capture into an MRPT rawlog of
// CObservationVelodyneScan.
#include <iostream>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/command_line.h"
#include "dlo/app/progress_bar.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/pcap_conversion.h"

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
  const dlo::CommandLine cl(argc, argv, {"--model"}, {"--quiet"});
  Arguments a;
  a.help = cl.help();
  if (a.help) return a;
  a.model = cl.text("--model");
  a.quiet = cl.flag("--quiet");
  if (cl.positional().size() != 2) {
    throw UsageError{"expected IN.pcap and OUT.rawlog, got " +
                     std::to_string(cl.positional().size()) + " arguments (see --help)."};
  }
  if (a.model.empty()) throw UsageError{"--model VLP16|HDL32|HDL64 is required."};
  a.pcap = cl.positional()[0];
  a.out = cl.positional()[1];
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
