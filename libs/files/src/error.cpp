#include "dlo/files/error.h"

#include <sstream>

namespace dlo {

namespace {

/// `s` without surrounding blanks, and with control characters (bytes of a corrupt file quoted
/// by MRPT) shown as '?'.
std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  std::string out = s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  }
  return out;
}

}  // namespace

std::string oneLineMessage(const std::exception& e) {
  const std::string what = e.what();
  const auto at = what.rfind("Message:");
  if (at != std::string::npos) {
    const std::string rest = what.substr(at + 8);
    const std::string message = trimmed(rest.substr(0, rest.find('\n')));
    if (!message.empty()) return message;
  }
  std::istringstream lines(what);
  for (std::string line; std::getline(lines, line);) {
    line = trimmed(line);
    if (line.rfind("Call stack backtrace:", 0) == 0) break;
    if (!line.empty() && line.rfind("====", 0) != 0) return line;
  }
  return "unknown error";
}

}  // namespace dlo
