/// \file program_options.h
/// \brief The command line of a DLO program, declared once: CLI11 parses it and generates --help
/// from the declarations; every mistake is thrown as a dlo::UsageError (exit status 2 through
/// dlo::runApp). CLI11 stays inside dlo_app: this header does not include it.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace dlo {

/// One declared option, to refine after declaring it.
class ProgramOption {
 public:
  explicit ProgramOption(CLI::Option* option) : option_(option) {}
  /// The option must be given (and not empty); \throw UsageError "--opt is required (see
  /// --help)." otherwise. --help marks it REQUIRED.
  ProgramOption& required();
  /// The name --help shows for the value ("FILE", "DIR", "N").
  ProgramOption& valueName(const std::string& name);
  /// The default --help shows, when the target's initial value is not it ("MAX_RANGE/100").
  ProgramOption& defaultText(const std::string& text);

 private:
  CLI::Option* option_;
};

/// A program's options: "--opt value" and "--opt=value", flags, repeatable options and
/// positional arguments. Option names are given with their dashes ("--out"); a target keeps its
/// value when the option is absent, and --help shows a non-empty one as the default.
///
/// The messages: "unknown option '--x' (see --help).", "unexpected argument 'x' (see --help).",
/// "--opt needs a value.", "--flag takes no value.", "--opt expects a number, got 'x'.",
/// "--opt expects a whole number, got 'x'.", "--opt is required (see --help).", "expected REF
/// and CUR, got 1 argument (see --help).". A single-value
/// option given twice keeps the last value.
class ProgramOptions {
 public:
  /// \param name the program's name, first in --help's usage line.
  /// \param description one paragraph: what the program does.
  ProgramOptions(const std::string& name, const std::string& description);
  ~ProgramOptions();
  ProgramOptions(const ProgramOptions&) = delete;
  ProgramOptions& operator=(const ProgramOptions&) = delete;

  /// An option with a text value.
  ProgramOption text(const std::string& name, std::string& target, const std::string& help);
  /// An option with a number (the whole text must be one).
  ProgramOption number(const std::string& name, double& target, const std::string& help);
  /// An option with a whole number ("3", also "3.0" or "3e0").
  ProgramOption wholeNumber(const std::string& name, long& target, const std::string& help);
  /// A repeatable option: every value, in order.
  ProgramOption repeatable(const std::string& name, std::vector<std::string>& target,
                           const std::string& help);
  /// A flag: true when given.
  void flag(const std::string& name, bool& target, const std::string& help);
  /// The next positional argument, in the order declared (an argument beyond the declared ones
  /// is an "unexpected argument"). Required, a missing one is "expected REF and CUR, got 1
  /// argument (see --help)."
  ProgramOption positional(const std::string& name, std::string& target, const std::string& help);
  /// Text --help prints after the options: outputs written, examples, exit status.
  void footer(const std::string& text);

  /// Parses the command line. -h or --help prints the help on stdout.
  /// \return false when the help was printed (the program then exits with status 0), true when
  /// the program should run.
  /// \throw UsageError for any mistake.
  bool parse(int argc, char** argv);
  /// Whether `name` was given on the command line (after parse()).
  bool given(const std::string& name) const;
  /// The generated help.
  std::string help() const;

 private:
  /// \throw UsageError for the first argument CLI11 did not place.
  void rejectExtras() const;
  /// \throw UsageError "expected REF and CUR, got 1 argument (see --help)." when a required
  /// positional argument is missing.
  void rejectMissingPositionals() const;
  /// An option's help, wrapped to the width of its column.
  static std::string describe(const std::string& help);

  std::unique_ptr<CLI::App> app_;
  std::vector<std::string> flags_;
  std::vector<std::string> positionals_;  ///< in the order declared
  std::string failure_;  ///< the sentence a value check left, for the error CLI11 throws then
};

}  // namespace dlo
