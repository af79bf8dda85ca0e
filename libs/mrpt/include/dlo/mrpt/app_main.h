/// \file app_main.h
/// \brief The error contract every DLO program shares: one line on stderr, a meaningful exit
/// status, never an abort or a stack of MRPT internals.
#pragma once

#include <functional>
#include <string>

namespace dlo {

/// A command-line mistake (unknown option, missing value): reported with exit status 2.
struct UsageError {
  std::string message;
};

/// Runs a program's body and turns what it throws into one line on stderr starting with
/// "`name`: " and an exit status: UsageError 2, InputError 1 (a bad file or parameter), any
/// other exception 1 (only its first line: MRPT exceptions carry a stack trace).
/// \return the body's own status when it returns normally.
int runApp(const char* name, const std::function<int()>& body);

}  // namespace dlo
