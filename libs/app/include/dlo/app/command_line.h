/// \file command_line.h
/// \brief The command-line parsing the DLO programs share: "--opt value" and "--opt=value",
/// flags, repeatable options, positional arguments and -h/--help, with every mistake thrown as a
/// dlo::UsageError (exit status 2 through dlo::runApp).
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace dlo {

/// The arguments of one program, checked against the options it knows.
///
/// Option names are given with their dashes ("--out"). An argument starting with "--" (other
/// than "--" itself) is an option; any other argument is positional. The first -h or --help
/// stops the parsing: what follows it is not looked at.
class CommandLine {
 public:
  /// \param options_with_value options that take a value, as "--opt value" or "--opt=value".
  /// \param flags options without a value.
  /// \throw UsageError "unknown option '--x' (see --help).", "--opt needs a value." when a value
  /// option ends the command line, "--flag takes no value." for "--flag=value".
  CommandLine(int argc, char** argv, std::set<std::string> options_with_value,
              std::set<std::string> flags);

  /// Whether -h or --help was given.
  bool help() const { return help_; }
  /// Whether the flag `name` was given.
  bool flag(const std::string& name) const;
  /// The value of the last occurrence of `name`, if any.
  std::optional<std::string> value(const std::string& name) const;
  /// The values of every occurrence of `name`, in order (repeatable options).
  std::vector<std::string> values(const std::string& name) const;
  /// The value of `name`, or "" when absent.
  std::string text(const std::string& name) const { return value(name).value_or(""); }
  /// The value of `name`; \throw UsageError "--opt is required (see --help)." when absent or
  /// empty.
  std::string required(const std::string& name) const;
  /// The value of `name` as a number, or `fallback` when absent.
  /// \throw UsageError "--opt expects a number, got 'x'."
  double number(const std::string& name, double fallback) const;
  /// The value of `name` as a whole number, or `fallback` when absent.
  /// \throw UsageError "--opt expects a number, got 'x'." or "--opt expects a whole number,
  /// got 'x'."
  long integer(const std::string& name, long fallback) const;
  /// The positional arguments, in order.
  const std::vector<std::string>& positional() const { return positional_; }
  /// \throw UsageError "unexpected argument 'x' (see --help)." when there is any positional
  /// argument.
  void rejectPositional() const;

  /// `text` as a number (the whole of it); \throw UsageError "`option` expects a number, got
  /// 'text'."
  static double toNumber(const std::string& option, const std::string& text);

 private:
  void checkKnown(const std::string& name) const;

  std::set<std::string> options_with_value_;
  std::set<std::string> flags_;
  std::vector<std::pair<std::string, std::string>> values_;
  std::set<std::string> flags_given_;
  std::vector<std::string> positional_;
  bool help_ = false;
};

}  // namespace dlo
