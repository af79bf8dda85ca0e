#include "dlo/app/program_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <exception>
#include <iostream>
#include <optional>
#include <utility>

#include "dlo/files/error.h"

namespace dlo {

namespace {

std::optional<double> parseNumber(const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

/// What follows an option instead of its value: another option (not a negative number).
bool looksLikeOption(const std::string& arg) {
  return arg.size() > 1 && arg[0] == '-' && !parseNumber(arg);
}

/// `text` with its lines broken at spaces to at most `width` characters where a word allows it.
std::string wrap(const std::string& text, size_t width) {
  std::string out;
  size_t line_start = 0;  // in `out`
  size_t last_space = std::string::npos;
  for (const char c : text) {
    if (c == '\n') {
      out += c;
      line_start = out.size();
      last_space = std::string::npos;
      continue;
    }
    if (c == ' ' && out.size() - line_start >= width) {
      out += '\n';
      line_start = out.size();
      last_space = std::string::npos;
      continue;
    }
    if (c == ' ') last_space = out.size();
    out += c;
    if (out.size() - line_start > width && last_space != std::string::npos) {
      out[last_space] = '\n';
      line_start = last_space + 1;
      last_space = std::string::npos;
    }
  }
  return out;
}

constexpr size_t kHelpWidth = 100;    ///< --help's lines
constexpr size_t kOptionColumn = 32;  ///< where the options' descriptions start

}  // namespace

ProgramOption& ProgramOption::required() {
  option_->required();
  return *this;
}

ProgramOption& ProgramOption::valueName(const std::string& name) {
  option_->type_name(name);
  return *this;
}

ProgramOption& ProgramOption::defaultText(const std::string& text) {
  option_->default_str(text);
  return *this;
}

ProgramOptions::ProgramOptions(const std::string& name, const std::string& description)
    : app_(std::make_unique<CLI::App>(wrap(description, kHelpWidth) + "\n", name)) {
  // Unknown arguments are collected, not thrown, so that the message can name them our way.
  app_->allow_extras();
  // An option given twice keeps the last value, as scripts that append an override expect.
  app_->option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app_->option_defaults()->always_capture_default();
  app_->get_formatter()->column_width(kOptionColumn);
}

ProgramOptions::~ProgramOptions() = default;

std::string ProgramOptions::describe(const std::string& help) {
  return wrap(help, kHelpWidth - kOptionColumn);
}

ProgramOption ProgramOptions::text(const std::string& name, std::string& target,
                                   const std::string& help) {
  return ProgramOption(app_->add_option(name, target, describe(help)));
}

ProgramOption ProgramOptions::number(const std::string& name, double& target,
                                     const std::string& help) {
  CLI::Option* option = app_->add_option(name, target, describe(help));
  option->check(CLI::Validator(
      [this, name](std::string& text) -> std::string {
        if (parseNumber(text)) return {};
        failure_ = name + " expects a number, got '" + text + "'.";
        return failure_;
      },
      ""));
  return ProgramOption(option);
}

ProgramOption ProgramOptions::wholeNumber(const std::string& name, long& target,
                                          const std::string& help) {
  CLI::Option* option = app_->add_option(name, target, describe(help));
  // Rewrites "3.0" or "3e0" to "3" before CLI11 converts it, as the numbers scripts pass may be
  // printed by a program that writes floats.
  option->transform(CLI::Validator(
      [this, name](std::string& text) -> std::string {
        const std::optional<double> x = parseNumber(text);
        if (!x) {
          failure_ = name + " expects a number, got '" + text + "'.";
          return failure_;
        }
        // 2^63: the doubles below it in magnitude convert to long.
        constexpr double kLimit = 9223372036854775808.0;
        if (!(std::isfinite(*x) && *x == std::floor(*x) && std::fabs(*x) < kLimit)) {
          failure_ = name + " expects a whole number, got '" + text + "'.";
          return failure_;
        }
        text = std::to_string(static_cast<long>(*x));
        return {};
      },
      ""));
  return ProgramOption(option);
}

ProgramOption ProgramOptions::repeatable(const std::string& name, std::vector<std::string>& target,
                                         const std::string& help) {
  CLI::Option* option = app_->add_option(name, target, describe(help));
  option->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->expected(1)
      ->allow_extra_args(false)
      ->default_str("");
  return ProgramOption(option);
}

void ProgramOptions::flag(const std::string& name, bool& target, const std::string& help) {
  app_->add_flag(name, target, describe(help));
  flags_.push_back(name);
}

ProgramOption ProgramOptions::positional(const std::string& name, std::string& target,
                                         const std::string& help) {
  positionals_.push_back(name);
  // The name says what it is ("REF", "OUT.rawlog"): no type after it.
  return ProgramOption(app_->add_option(name, target, describe(help))->type_name(""));
}

void ProgramOptions::footer(const std::string& text) {
  app_->footer(text);
}

bool ProgramOptions::parse(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  for (const std::string& arg : args) {
    if (arg == "--") break;
    const auto eq = arg.find('=');
    if (eq == std::string::npos) continue;
    for (const std::string& flag : flags_) {
      if (arg.compare(0, eq, flag) == 0 && eq == flag.size()) {
        throw UsageError{flag + " takes no value."};
      }
    }
  }
  failure_.clear();
  try {
    app_->parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << help();
    return false;
  } catch (const CLI::RequiredError& e) {
    rejectExtras();  // an unknown option explains a missing one better than the reverse
    rejectMissingPositionals();
    throw UsageError{std::string(e.what()) + " (see --help)."};
  } catch (const CLI::ArgumentMismatch& e) {
    // The option left without its value: last on the line, or followed by another option.
    for (size_t i = 0; i < args.size() && args[i] != "--"; ++i) {
      const CLI::Option* option = looksLikeOption(args[i]) && args[i].find('=') == std::string::npos
                                      ? app_->get_option_no_throw(args[i])
                                      : nullptr;
      if (option && option->get_type_size() > 0 &&
          (i + 1 == args.size() || looksLikeOption(args[i + 1]))) {
        throw UsageError{args[i] + " needs a value."};
      }
    }
    for (const std::string& arg : args) {
      if (arg.size() > 1 && arg.back() == '=' &&
          app_->get_option_no_throw(arg.substr(0, arg.size() - 1))) {
        throw UsageError{arg.substr(0, arg.size() - 1) + " needs a value."};
      }
    }
    throw UsageError{std::string(e.what()) + "."};
  } catch (const CLI::ParseError& e) {
    if (!failure_.empty()) throw UsageError{failure_};
    throw UsageError{std::string(e.what()) + " (see --help)."};
  }
  rejectExtras();
  for (const CLI::Option* option : app_->get_options()) {
    if (!option->get_required()) continue;
    bool empty = true;
    for (const std::string& r : option->results()) empty = empty && r.empty();
    if (empty) throw UsageError{option->get_name() + " is required (see --help)."};
  }
  return true;
}

void ProgramOptions::rejectExtras() const {
  for (const std::string& extra : app_->remaining()) {
    if (looksLikeOption(extra)) {
      throw UsageError{"unknown option '" + extra.substr(0, extra.find('=')) + "' (see --help)."};
    }
    throw UsageError{"unexpected argument '" + extra + "' (see --help)."};
  }
}

void ProgramOptions::rejectMissingPositionals() const {
  std::string names;
  size_t given = 0;
  bool missing = false;
  for (size_t i = 0; i < positionals_.size(); ++i) {
    const CLI::Option* option = app_->get_option(positionals_[i]);
    given += option->count();
    missing = missing || (option->get_required() && option->count() == 0);
    names += (i == 0 ? "" : i + 1 == positionals_.size() ? " and " : ", ") + positionals_[i];
  }
  if (missing) {
    throw UsageError{"expected " + names + ", got " + std::to_string(given) +
                     (given == 1 ? " argument" : " arguments") + " (see --help)."};
  }
}

bool ProgramOptions::given(const std::string& name) const {
  const CLI::Option* option = app_->get_option_no_throw(name);
  if (!option) throw std::logic_error("ProgramOptions: option '" + name + "' was not declared.");
  return option->count() > 0;
}

std::string ProgramOptions::help() const {
  return app_->help();
}

}  // namespace dlo
