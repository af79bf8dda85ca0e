/// \file app_main.h
/// \brief The error contract every DLO program shares: one line on stderr, a meaningful exit
/// status, never an abort or a stack of MRPT internals.
#pragma once

#include <functional>

#include "dlo/files/error.h"

namespace dlo {

/// Runs a program's body and turns what it throws into one line on stderr starting with
/// "`name`: " and an exit status: UsageError 2 (a command-line mistake), any other dlo::Error 1
/// (InputError: a bad file or parameter; OutputError: an output that cannot be written), any
/// other exception 1 (only its first line: MRPT exceptions carry a stack trace).
/// \return the body's own status when it returns normally.
int runApp(const char* name, const std::function<int()>& body);

}  // namespace dlo
