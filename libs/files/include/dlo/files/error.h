/// \file error.h
/// \brief The errors a user can cause (a missing file, a bad format or value, an output that
/// cannot be written): one small family under dlo::Error, which dlo::runApp turns into one line
/// on stderr and an exit status (dlo/app/app_main.h).
#pragma once

#include <stdexcept>
#include <string>

namespace dlo {

/// Base of the errors a user can cause and fix. what() is one sentence naming the file, option
/// or key at fault and what was expected.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// A bad input: a missing or malformed file, a parameter out of range (exit status 1).
class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(message) {}
};

/// An output that cannot be written: a folder missing or not writable, a full disk, an encoder
/// that fails (exit status 1).
class OutputError : public Error {
 public:
  explicit OutputError(const std::string& message) : Error(message) {}
};

/// A command-line mistake: an unknown option, a missing or bad value (exit status 2).
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& message) : Error(message) {}
};

/// The message of `e` as one line for a user, to quote inside an InputError: MRPT's exceptions
/// span several lines ("==== MRPT exception ====", nested "Message:" parts, a call stack), of
/// which this keeps the innermost message; other exceptions give their first line.
std::string oneLineMessage(const std::exception& e);

}  // namespace dlo
