#include "dlo/mrpt/param_table.h"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "dlo/files/error.h"

namespace dlo::param_text {

std::string sectionName(const std::string& prefix, const std::string& section) {
  return prefix.empty() ? section : prefix + "." + section;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

double parse(const std::string& text, bool is_int, const std::string& name,
             const std::string& where) {
  const std::string v = trim(text);
  const char* begin = v.c_str();
  char* end = nullptr;
  errno = 0;
  if (is_int) {
    const long long x = std::strtoll(begin, &end, 10);
    if (v.empty() || *end != '\0' || errno == ERANGE || x < std::numeric_limits<int>::min() ||
        x > std::numeric_limits<int>::max()) {
      throw InputError("parameter " + name + " = '" + v + "' (" + where + ") is not an integer.");
    }
    return static_cast<double>(x);
  }
  const double x = std::strtod(begin, &end);
  if (v.empty() || *end != '\0' || errno == ERANGE) {
    throw InputError("parameter " + name + " = '" + v + "' (" + where + ") is not a number.");
  }
  return x;
}

std::string comment(const std::string& text) {
  constexpr size_t kWidth = 100;
  std::string out, line;
  std::istringstream words(text);
  std::string word;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > kWidth) {
      out += line + "\n";
      line.clear();
    }
    line += line.empty() ? "; " + word : " " + word;
  }
  if (!line.empty()) out += line + "\n";
  return out;
}

std::string nameList(const std::vector<NamedValue>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " or " : ", ";
    out += names[i].name;
  }
  return out;
}

double parseNamed(const std::string& text, const std::vector<NamedValue>& names,
                  const std::string& name, const std::string& where) {
  const std::string v = trim(text);
  for (const NamedValue& n : names) {
    if (v == n.name) return n.value;
  }
  // The numbers these keys took before they had names (odometry.reference = 3, deskew = 1).
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (!v.empty() && *end == '\0') {
    for (const NamedValue& n : names) {
      if (x == n.value) {
        throw InputError("parameter " + name + " = '" + v + "' (" + where +
                         ") is the old numeric form: write " + name + " = " + n.name + " (one of " +
                         nameList(names) + ").");
      }
    }
  }
  throw InputError("parameter " + name + " = '" + v + "' (" + where + ") must be one of " +
                   nameList(names) + ".");
}

std::string named(double x, const std::vector<NamedValue>& names) {
  for (const NamedValue& n : names) {
    if (n.value == x) return n.name;
  }
  return exact(x, true);
}

std::string exact(double x, bool is_int) {
  if (is_int) return std::to_string(static_cast<long long>(x));
  // Shortest text that reads back exactly: 0.1 rather than 0.10000000000000001.
  for (int precision = 6; precision <= 17; ++precision) {
    std::ostringstream s;
    s.precision(precision);
    s << x;
    if (std::strtod(s.str().c_str(), nullptr) == x) return s.str();
  }
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

void throwIfProblem(const std::string& problem) {
  if (!problem.empty()) throw InputError(problem);
}

void fail(const std::string& problem) {
  throw InputError(problem);
}

void requireReadableConfig(const std::string& path) {
  if (!std::ifstream(path)) {
    throw InputError("cannot open config file '" + path + "': no such file or not readable.");
  }
}

void rethrowWithFile(const std::string& path, const std::exception& e) {
  // An InputError is already one sentence; MRPT's parser errors come with a call stack.
  const std::string why = dynamic_cast<const InputError*>(&e) ? e.what() : oneLineMessage(e);
  throw InputError("config file '" + path + "': " + why);
}

}  // namespace dlo::param_text
