/// \file range_message.h
/// \brief The sentence every parameter check uses for a value out of range.
#pragma once

#include <sstream>
#include <string>

namespace dlo {

/// "parameter KEY = VALUE is out of range: expected EXPECTED."
template <typename T>
std::string outOfRange(const char* key, T value, const char* expected) {
  std::ostringstream s;
  s << "parameter " << key << " = " << value << " is out of range: expected " << expected << ".";
  return s.str();
}

}  // namespace dlo
