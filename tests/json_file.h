/// \file json_file.h
/// \brief A JSON file a program wrote (report.json, metrics.json), parsed for a test to check.
#pragma once

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace dlo::test {

/// The JSON document in `path`.
/// \throws std::runtime_error naming the file if it cannot be opened, nlohmann::json::parse_error
/// if it is not JSON: either fails the test that calls it, with the reason.
inline nlohmann::json readJsonFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  return nlohmann::json::parse(in);
}

}  // namespace dlo::test
