#include "dlo/app/command_line.h"

#include <cmath>
#include <exception>
#include <stdexcept>
#include <utility>

#include "dlo/files/error.h"

namespace dlo {

CommandLine::CommandLine(int argc, char** argv, std::set<std::string> options_with_value,
                         std::set<std::string> flags)
    : options_with_value_(std::move(options_with_value)), flags_(std::move(flags)) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      help_ = true;
      return;
    }
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      positional_.push_back(arg);
      continue;
    }
    const auto eq = arg.find('=');
    const std::string name = arg.substr(0, eq);
    if (flags_.count(name)) {
      if (eq != std::string::npos) throw UsageError{name + " takes no value."};
      flags_given_.insert(name);
    } else if (options_with_value_.count(name)) {
      if (eq != std::string::npos) {
        values_.emplace_back(name, arg.substr(eq + 1));
      } else {
        if (i + 1 >= argc) throw UsageError{name + " needs a value."};
        values_.emplace_back(name, argv[++i]);
      }
    } else {
      throw UsageError{"unknown option '" + name + "' (see --help)."};
    }
  }
}

void CommandLine::checkKnown(const std::string& name) const {
  // A programming error, not a user's: the program asks for an option it did not declare.
  if (!options_with_value_.count(name) && !flags_.count(name)) {
    throw std::logic_error("CommandLine: option '" + name + "' was not declared.");
  }
}

bool CommandLine::flag(const std::string& name) const {
  checkKnown(name);
  return flags_given_.count(name) > 0;
}

std::optional<std::string> CommandLine::value(const std::string& name) const {
  checkKnown(name);
  std::optional<std::string> last;
  for (const auto& [option, value] : values_) {
    if (option == name) last = value;
  }
  return last;
}

std::vector<std::string> CommandLine::values(const std::string& name) const {
  checkKnown(name);
  std::vector<std::string> all;
  for (const auto& [option, value] : values_) {
    if (option == name) all.push_back(value);
  }
  return all;
}

std::string CommandLine::required(const std::string& name) const {
  const std::optional<std::string> v = value(name);
  if (!v || v->empty()) throw UsageError{name + " is required (see --help)."};
  return *v;
}

double CommandLine::toNumber(const std::string& option, const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  throw UsageError{option + " expects a number, got '" + text + "'."};
}

double CommandLine::number(const std::string& name, double fallback) const {
  const std::optional<std::string> v = value(name);
  return v ? toNumber(name, *v) : fallback;
}

long CommandLine::integer(const std::string& name, long fallback) const {
  const std::optional<std::string> v = value(name);
  if (!v) return fallback;
  const double x = toNumber(name, *v);
  // 2^63: the doubles below it in magnitude convert to long.
  constexpr double kLimit = 9223372036854775808.0;
  if (!(std::isfinite(x) && x == std::floor(x) && std::fabs(x) < kLimit)) {
    throw UsageError{name + " expects a whole number, got '" + *v + "'."};
  }
  return static_cast<long>(x);
}

void CommandLine::rejectPositional() const {
  if (!positional_.empty()) {
    throw UsageError{"unexpected argument '" + positional_.front() + "' (see --help)."};
  }
}

}  // namespace dlo
