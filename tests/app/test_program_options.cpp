// dlo::ProgramOptions through dlo::runApp, as a program sees it: both option syntaxes, flags,
// repeatable options, numbers, positionals, the generated --help, and every mistake as one
// sentence naming the option with exit status 2.
#include "dlo/app/program_options.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/scan_input_options.h"

namespace dlo {
namespace {

/// argv for `args`, with a program name in front; the strings live as long as the object.
class Argv {
 public:
  Argv(std::initializer_list<std::string> args) : Argv(std::vector<std::string>(args)) {}
  explicit Argv(const std::vector<std::string>& args) : strings_{"prog"} {
    strings_.insert(strings_.end(), args.begin(), args.end());
    for (std::string& s : strings_) pointers_.push_back(s.data());
    pointers_.push_back(nullptr);
  }
  int argc() const { return static_cast<int>(strings_.size()); }
  char** argv() { return pointers_.data(); }

 private:
  std::vector<std::string> strings_;
  std::vector<char*> pointers_;
};

/// What a small program declaring every kind of option parsed.
struct Parsed {
  std::string out = "default-out", input, ref;
  std::vector<std::string> sets;
  double rate = 2.5;
  long count = -1;
  bool quiet = false;
};

/// A run of the small program: its exit status, stdout, stderr and what it parsed.
struct ProgramRun {
  int status = -1;
  std::string out, err;
  Parsed parsed;
};

ProgramRun run(std::initializer_list<std::string> args) {
  Argv a(args);
  ProgramRun r;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  r.status = runApp("prog", [&] {
    ProgramOptions cl("prog", "Does what a test needs.");
    cl.positional("REF", r.parsed.ref, "a positional argument");
    cl.text("--input", r.parsed.input, "the input file").valueName("FILE").required();
    cl.text("--out", r.parsed.out, "the output folder").valueName("DIR");
    cl.repeatable("--set", r.parsed.sets, "one override; may be repeated")
        .valueName("section.key=value");
    cl.number("--rate", r.parsed.rate, "a rate in hertz").valueName("HZ");
    cl.wholeNumber("--count", r.parsed.count, "how many (-1: all)").valueName("N");
    cl.flag("--quiet", r.parsed.quiet, "no progress");
    cl.footer("Exit status: 0 on success, 2 for a command-line error.");
    return cl.parse(a.argc(), a.argv()) ? 0 : 7;  // 7: help shown (runApp's caller maps it to 0)
  });
  r.out = testing::internal::GetCapturedStdout();
  r.err = testing::internal::GetCapturedStderr();
  return r;
}

/// A command-line mistake: status 2, nothing on stdout, exactly `message` on stderr.
void expectUsageError(std::initializer_list<std::string> args, const std::string& message) {
  const ProgramRun r = run(args);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "prog: " + message + "\n");
}

TEST(ProgramOptions, AcceptsBothOptionSyntaxes) {
  const ProgramRun spaced = run({"--input", "in", "--out", "dir", "--rate", "4"});
  ASSERT_EQ(spaced.status, 0) << spaced.err;
  EXPECT_EQ(spaced.parsed.out, "dir");
  EXPECT_EQ(spaced.parsed.rate, 4.0);
  const ProgramRun joined = run({"--input=in", "--out=dir", "--rate=4"});
  ASSERT_EQ(joined.status, 0) << joined.err;
  EXPECT_EQ(joined.parsed.input, "in");
  EXPECT_EQ(joined.parsed.out, "dir");
  EXPECT_EQ(joined.parsed.rate, 4.0);
}

TEST(ProgramOptions, AbsentOptionsKeepTheirDefaults) {
  const ProgramRun r = run({"--input", "in"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.parsed.out, "default-out");
  EXPECT_EQ(r.parsed.rate, 2.5);
  EXPECT_EQ(r.parsed.count, -1);
  EXPECT_FALSE(r.parsed.quiet);
  EXPECT_TRUE(r.parsed.sets.empty());
  EXPECT_EQ(r.parsed.ref, "");
}

TEST(ProgramOptions, RepeatedOptionsKeepEveryValueAndTheLastWins) {
  const ProgramRun r = run({"--input", "in", "--set", "a.b=1", "--out", "x", "--set=c.d=2", "--out",
                            "y", "--quiet", "ref.bin"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.parsed.sets, (std::vector<std::string>{"a.b=1", "c.d=2"}));
  EXPECT_EQ(r.parsed.out, "y");
  EXPECT_TRUE(r.parsed.quiet);
  EXPECT_EQ(r.parsed.ref, "ref.bin");
}

TEST(ProgramOptions, NumbersIncludingNegativeAndWholeOnesWrittenAsFloats) {
  const ProgramRun r = run({"--input", "in", "--rate", "-0.5", "--count", "-3"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.parsed.rate, -0.5);
  EXPECT_EQ(r.parsed.count, -3);
  EXPECT_EQ(run({"--input", "in", "--count=3.0"}).parsed.count, 3);
  EXPECT_EQ(run({"--input", "in", "--count", "2e3"}).parsed.count, 2000);
}

TEST(ProgramOptions, ANonNumericNumberIsNamed) {
  expectUsageError({"--input", "in", "--rate", "fast"}, "--rate expects a number, got 'fast'.");
  expectUsageError({"--input", "in", "--rate=2x"}, "--rate expects a number, got '2x'.");
  expectUsageError({"--input", "in", "--count", "many"}, "--count expects a number, got 'many'.");
  expectUsageError({"--input", "in", "--count", "2.5"},
                   "--count expects a whole number, got '2.5'.");
  expectUsageError({"--input", "in", "--count", "1e30"},
                   "--count expects a whole number, got '1e30'.");
}

TEST(ProgramOptions, AnUnknownOptionIsNamed) {
  expectUsageError({"--input", "in", "--frobnicate"},
                   "unknown option '--frobnicate' (see --help).");
  expectUsageError({"--input", "in", "--frobnicate=3"},
                   "unknown option '--frobnicate' (see --help).");
  expectUsageError({"--input", "in", "-x"}, "unknown option '-x' (see --help).");
  // Named before a missing required option: it is the likelier mistake (a misspelt --input).
  expectUsageError({"--inptu", "in"}, "unknown option '--inptu' (see --help).");
}

TEST(ProgramOptions, AnArgumentBeyondThePositionalOnesIsNamed) {
  expectUsageError({"--input", "in", "a.bin", "b.bin"},
                   "unexpected argument 'b.bin' (see --help).");
}

TEST(ProgramOptions, AMissingValueIsNamed) {
  expectUsageError({"--input", "in", "--out"}, "--out needs a value.");
  expectUsageError({"--input", "in", "--out="}, "--out needs a value.");
  expectUsageError({"--input", "in", "--set"}, "--set needs a value.");
  expectUsageError({"--input", "in", "--rate"}, "--rate needs a value.");
}

TEST(ProgramOptions, AMissingPositionalArgumentIsNamedWithTheOthers) {
  const auto message = [](std::initializer_list<std::string> args) {
    ProgramOptions cl("prog", "Registers CUR against REF.");
    std::string ref, cur;
    cl.positional("REF", ref, "the reference scan").required();
    cl.positional("CUR", cur, "the current scan").required();
    Argv a(args);
    try {
      cl.parse(a.argc(), a.argv());
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message({}), "expected REF and CUR, got 0 arguments (see --help).");
  EXPECT_EQ(message({"a.bin"}), "expected REF and CUR, got 1 argument (see --help).");
  EXPECT_EQ(message({"a.bin", "b.bin"}), "");
  EXPECT_EQ(message({"a.bin", "--bogus"}), "unknown option '--bogus' (see --help).");
}

TEST(ProgramOptions, AFlagTakesNoValue) {
  expectUsageError({"--input", "in", "--quiet=yes"}, "--quiet takes no value.");
}

TEST(ProgramOptions, AMissingRequiredOptionIsNamed) {
  expectUsageError({}, "--input is required (see --help).");
  expectUsageError({"--out", "dir"}, "--input is required (see --help).");
  expectUsageError({"--input="}, "--input needs a value.");
}

TEST(ProgramOptions, HelpGoesToStdoutWithEveryOptionAndStopsTheProgram) {
  for (const char* help : {"--help", "-h"}) {
    // Help wins over a missing required option and over the mistakes after it.
    const ProgramRun r = run({help, "--frobnicate"});
    EXPECT_EQ(r.status, 7) << help;
    EXPECT_EQ(r.err, "") << help;
    for (const char* expected :
         {"Does what a test needs.", "Usage: prog [OPTIONS] [REF]", "REF", "--input FILE REQUIRED",
          "the input file", "--out DIR=default-out", "--set section.key=value",
          "one override; may be repeated", "--rate HZ=2.5", "--count N=-1", "--quiet",
          "no progress", "-h,--help", "Exit status: 0 on success"}) {
      EXPECT_NE(r.out.find(expected), std::string::npos) << help << ": no '" << expected << "' in\n"
                                                         << r.out;
    }
  }
}

TEST(ProgramOptions, AskingWhetherAnUndeclaredOptionWasGivenIsAProgrammingError) {
  ProgramOptions cl("prog", "Does nothing.");
  Argv a({});
  ASSERT_TRUE(cl.parse(a.argc(), a.argv()));
  EXPECT_THROW(cl.given("--nope"), std::logic_error);
}

TEST(ProgramOptions, LongHelpIsWrappedToOneHundredColumns) {
  std::string words;
  for (int i = 0; i < 60; ++i) words += "word" + std::to_string(i) + " ";
  ProgramOptions cl("prog", words);
  std::string target;
  cl.text("--long", target, words);
  const std::string help = cl.help();
  EXPECT_NE(help.find("word59"), std::string::npos) << help;
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);) EXPECT_LE(line.size(), 100u) << line;
}

/// A program reading a drive, with the shared scan options in `which`: its status, stderr and
/// what it parsed.
struct ScanRun {
  int status = -1;
  std::string err, help;
  ScanInputOptions parsed;
};

ScanRun runScans(unsigned which, const std::vector<std::string>& args) {
  Argv a(args);
  ScanRun r;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  r.status = runApp("prog", [&] {
    ProgramOptions cl("prog", "Reads a drive.");
    declareScanInputOptions(cl, r.parsed, which);
    if (!cl.parse(a.argc(), a.argv())) return 0;
    checkScanInputOptions(r.parsed);
    return 0;
  });
  r.help = testing::internal::GetCapturedStdout();
  r.err = testing::internal::GetCapturedStderr();
  return r;
}

TEST(ScanInputOptions, DeclaredOnceForEveryProgramThatReadsADrive) {
  const ScanRun r =
      runScans(kScanAll, {"--model", "VLP16", "--sensor-label", "lidar", "--min-range", "1.5",
                          "--max-range", "80", "--max-frames", "25"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.parsed.model, "VLP16");
  EXPECT_EQ(r.parsed.sensor_label, "lidar");
  EXPECT_DOUBLE_EQ(r.parsed.min_range, 1.5);
  EXPECT_DOUBLE_EQ(r.parsed.max_range, 80.0);
  EXPECT_EQ(r.parsed.max_frames, 25);
  // The defaults, and --help showing them.
  const ScanRun d = runScans(kScanAll, {});
  ASSERT_EQ(d.status, 0);
  EXPECT_DOUBLE_EQ(d.parsed.min_range, 2.0);
  EXPECT_DOUBLE_EQ(d.parsed.max_range, 120.0);
  EXPECT_EQ(d.parsed.max_frames, -1);
  const ScanRun h = runScans(kScanAll, {"--help"});
  EXPECT_NE(h.help.find("--min-range M=2"), std::string::npos) << h.help;
  EXPECT_NE(h.help.find("--max-frames N=-1"), std::string::npos) << h.help;
}

TEST(ScanInputOptions, AProgramTakesOnlyTheOnesItDeclares) {
  const ScanRun r = runScans(kScanRange, {"--model", "VLP16"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--model"), std::string::npos) << r.err;
  const ScanRun h = runScans(kScanRange | kScanMaxFrames, {"--help"});
  EXPECT_EQ(h.help.find("--sensor-label"), std::string::npos) << h.help;
  EXPECT_NE(h.help.find("--max-frames"), std::string::npos) << h.help;
}

TEST(ScanInputOptions, RangesAndScanCountsOutOfRangeAreNamed) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--min-range", "-1"}, {"--max-range", "1"}, {"--min-range", "5", "--max-range", "5"}}) {
    const ScanRun r = runScans(kScanAll, args);
    EXPECT_EQ(r.status, 2) << args[0];
    EXPECT_EQ(r.err, "prog: --min-range and --max-range must satisfy 0 <= min < max.\n");
  }
  for (const std::string n : {"0", "-2"}) {
    const ScanRun r = runScans(kScanAll, {"--max-frames", n});
    EXPECT_EQ(r.status, 2) << n;
    EXPECT_EQ(r.err, "prog: --max-frames expects a whole number of scans >= 1, or -1 for all.\n");
  }
}

}  // namespace
}  // namespace dlo
