// Helpers shared by the tests that run the built programs: reading their output files and
// quoting their arguments for the shell.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

namespace dlo::test {

/// What a program run produced.
struct RunResult {
  int status = -1;
  std::string out;
  std::string err;
};

/// The whole content of a file ("" if it cannot be read).
inline std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Single-quotes an argument for /bin/sh.
inline std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace dlo::test
