/// \file json_text.h
/// \brief The two pieces every JSON report of the project needs: numbers and strings.
#pragma once

#include <string>

namespace dlo {

/// `v` with `significant_digits` (printf "%.*g"); JSON has no NaN or infinity, so those become
/// null and the file stays parseable.
std::string jsonNumber(double v, int significant_digits);

/// `text` as a JSON string literal, quotes included, with control characters escaped.
std::string jsonString(const std::string& text);

}  // namespace dlo
