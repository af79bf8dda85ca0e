// dlo::CommandLine: both option syntaxes, flags, repeatable options, numbers, positionals, help,
// and the usage errors with their messages.
#include "dlo/app/command_line.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"

namespace dlo {
namespace {

/// argv for `args`, with a program name in front; the strings live as long as the object.
class Argv {
 public:
  Argv(std::initializer_list<std::string> args) : strings_{"prog"} {
    strings_.insert(strings_.end(), args);
    for (std::string& s : strings_) pointers_.push_back(s.data());
    pointers_.push_back(nullptr);
  }
  int argc() const { return static_cast<int>(strings_.size()); }
  char** argv() { return pointers_.data(); }

 private:
  std::vector<std::string> strings_;
  std::vector<char*> pointers_;
};

CommandLine parse(std::initializer_list<std::string> args) {
  Argv a(args);
  return CommandLine(a.argc(), a.argv(), {"--out", "--set", "--rate", "--count"}, {"--quiet"});
}

/// The UsageError message `f` throws, or "" when it throws none.
template <typename F>
std::string usageError(F f) {
  try {
    f();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(CommandLine, AcceptsBothOptionSyntaxes) {
  const CommandLine spaced = parse({"--out", "dir"});
  EXPECT_EQ(spaced.value("--out"), "dir");
  const CommandLine joined = parse({"--out=dir"});
  EXPECT_EQ(joined.value("--out"), "dir");
  EXPECT_EQ(parse({"--out="}).value("--out"), "");
  EXPECT_EQ(parse({"--set=a.b=1"}).value("--set"), "a.b=1");         // only the first '=' splits
  EXPECT_EQ(parse({"--out", "--quiet"}).value("--out"), "--quiet");  // a value may look like one
}

TEST(CommandLine, AbsentOptionsAndFlags) {
  const CommandLine cl = parse({});
  EXPECT_FALSE(cl.value("--out"));
  EXPECT_EQ(cl.text("--out"), "");
  EXPECT_TRUE(cl.values("--set").empty());
  EXPECT_FALSE(cl.flag("--quiet"));
  EXPECT_FALSE(cl.help());
  EXPECT_TRUE(cl.positional().empty());
  EXPECT_TRUE(parse({"--quiet"}).flag("--quiet"));
  EXPECT_EQ(usageError([] { parse({"--quiet=1"}); }), "--quiet takes no value.");
}

TEST(CommandLine, RepeatedOptionsKeepEveryValueAndTheLastWins) {
  const CommandLine cl = parse({"--set", "a=1", "--out", "x", "--set=b=2", "--out", "y"});
  EXPECT_EQ(cl.values("--set"), (std::vector<std::string>{"a=1", "b=2"}));
  EXPECT_EQ(cl.value("--set"), "b=2");
  EXPECT_EQ(cl.value("--out"), "y");
}

TEST(CommandLine, Numbers) {
  const CommandLine cl = parse({"--rate", "2.5", "--count=-3"});
  EXPECT_DOUBLE_EQ(cl.number("--rate", 1.0), 2.5);
  EXPECT_EQ(cl.integer("--count", 7), -3);
  EXPECT_DOUBLE_EQ(parse({}).number("--rate", 1.5), 1.5);
  EXPECT_EQ(parse({}).integer("--count", 7), 7);
  EXPECT_DOUBLE_EQ(parse({"--rate", "1e3"}).number("--rate", 0.0), 1000.0);
  EXPECT_EQ(usageError([] {
              parse({"--rate", "fast"}).number("--rate", 0.0);
            }),
            "--rate expects a number, got 'fast'.");
  EXPECT_EQ(usageError([] {
              parse({"--rate", "2x"}).number("--rate", 0.0);
            }),
            "--rate expects a number, got '2x'.");
  EXPECT_EQ(usageError([] { parse({"--rate="}).number("--rate", 0.0); }),
            "--rate expects a number, got ''.");
  EXPECT_EQ(usageError([] {
              parse({"--count", "ten"}).integer("--count", 0);
            }),
            "--count expects a number, got 'ten'.");
  EXPECT_EQ(usageError([] {
              parse({"--count", "2.5"}).integer("--count", 0);
            }),
            "--count expects a whole number, got '2.5'.");
}

TEST(CommandLine, Required) {
  EXPECT_EQ(parse({"--out", "d"}).required("--out"), "d");
  EXPECT_EQ(usageError([] { parse({}).required("--out"); }), "--out is required (see --help).");
  EXPECT_EQ(usageError([] { parse({"--out="}).required("--out"); }),
            "--out is required (see --help).");
}

TEST(CommandLine, UnknownOptionIsAUsageError) {
  EXPECT_EQ(usageError([] { parse({"--frobnicate"}); }),
            "unknown option '--frobnicate' (see --help).");
  EXPECT_EQ(usageError([] { parse({"--frobnicate=3"}); }),
            "unknown option '--frobnicate' (see --help).");
}

TEST(CommandLine, MissingValueIsAUsageError) {
  EXPECT_EQ(usageError([] { parse({"--quiet", "--out"}); }), "--out needs a value.");
}

TEST(CommandLine, Positionals) {
  const CommandLine cl = parse({"a.bin", "--out", "d", "b.bin", "-x", "--"});
  EXPECT_EQ(cl.positional(), (std::vector<std::string>{"a.bin", "b.bin", "-x", "--"}));
  EXPECT_EQ(cl.value("--out"), "d");
  EXPECT_EQ(usageError([&] { cl.rejectPositional(); }),
            "unexpected argument 'a.bin' (see --help).");
  EXPECT_EQ(usageError([] { parse({"--out", "d"}).rejectPositional(); }), "");
}

TEST(CommandLine, HelpStopsTheParsing) {
  EXPECT_TRUE(parse({"--help"}).help());
  EXPECT_TRUE(parse({"-h"}).help());
  // What follows --help is not looked at, mistakes included.
  EXPECT_TRUE(parse({"--out", "d", "--help", "--frobnicate", "--out"}).help());
  // What precedes it is.
  EXPECT_EQ(usageError([] {
              parse({"--frobnicate", "--help"});
            }),
            "unknown option '--frobnicate' (see --help).");
}

TEST(CommandLine, UndeclaredOptionIsAProgrammingError) {
  EXPECT_THROW(parse({}).value("--undeclared"), std::logic_error);
  EXPECT_THROW(parse({}).flag("--undeclared"), std::logic_error);
}

}  // namespace
}  // namespace dlo
