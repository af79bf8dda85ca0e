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

}  // namespace dlo
