// dlo-pcap2rawlog: converts a Velodyne .pcap capture into an MRPT rawlog of
// CObservationVelodyneScan.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/app/progress_bar.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/pcap_conversion.h"

namespace {

constexpr const char* kDescription =
    "Converts a Velodyne packet capture into an MRPT rawlog, one rotation in memory at a time.";

constexpr const char* kFooter =
    R"(Output: OUT.rawlog (OUT.rawlog.gz is gzip-compressed), observation-only layout, one
CObservationVelodyneScan per full rotation (raw packets plus the model's default calibration,
sensorLabel "Velodyne_SCAN"); GPS packets set the timestamps but are not written. As with MRPT's
driver, the partial rotation after the last 360-degree wrap is not written; the first one may be
partial if the capture starts mid-turn. Written to OUT.tmp and renamed at the end, so an
existing OUT is never half-overwritten.

Exit status: 0 on success, 1 for a bad input, 2 for a command-line error; errors are one line
on stderr starting with "dlo-pcap2rawlog: ".)";

using dlo::UsageError;

struct Arguments {
  std::string pcap;
  std::string out;
  std::string model;
  bool quiet = false;
};

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  dlo::ProgramOptions cl("dlo-pcap2rawlog", kDescription);
  cl.positional("IN.pcap", a.pcap, "the Velodyne capture").required();
  cl.positional("OUT.rawlog", a.out, "the rawlog to write").required();
  cl.text("--model", a.model, "sensor model: VLP16, HDL32 or HDL64 (a capture does not say)")
      .valueName("MODEL")
      .required();
  cl.flag("--quiet", a.quiet, "no progress and no summary");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
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
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
