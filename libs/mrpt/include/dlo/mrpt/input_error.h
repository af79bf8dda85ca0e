/// \file input_error.h
/// \brief The exception for problems a user can cause: missing files, bad formats, bad values.
#pragma once

#include <stdexcept>
#include <string>

namespace dlo {

/// Thrown for user-caused input problems. what() is one sentence that names the file or key and
/// what was expected; apps print it and exit non-zero.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// The message of `e` as one line for a user, to quote inside an InputError: MRPT's exceptions
/// span several lines ("==== MRPT exception ====", nested "Message:" parts, a call stack), of
/// which this keeps the innermost message; other exceptions give their first line.
std::string oneLineMessage(const std::exception& e);

}  // namespace dlo
