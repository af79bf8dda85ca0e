#include "dlo/export/atomic_file.h"

#include <filesystem>
#include <fstream>

namespace dlo {

namespace {

/// First line of an exception message, without trailing punctuation, to fit in one sentence.
std::string firstLine(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == '.' || line.back() == ' ' || line.back() == '\r')) {
    line.pop_back();
  }
  return line;
}

}  // namespace

void writeAtomically(const std::string& path,
                     const std::function<void(const std::string& temp)>& write) {
  namespace fs = std::filesystem;
  const std::string temp = path + ".tmp";
  std::error_code ec;
  try {
    write(temp);
  } catch (const std::exception& e) {
    fs::remove(temp, ec);
    throw ExportError("cannot write '" + path + "' (" + firstLine(e.what()) + ").");
  }
  if (!fs::is_regular_file(temp, ec)) {
    throw ExportError("cannot write '" + path + "' (the writer produced no file).");
  }
  fs::rename(temp, path, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw ExportError("cannot write '" + path +
                      "' (renaming the temporary file failed: " + ec.message() + ").");
  }
}

void writeBytesAtomically(const std::string& path, const std::vector<unsigned char>& bytes) {
  writeAtomically(path, [&](const std::string& temp) {
    std::ofstream out(temp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot create '" + temp + "'");
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("writing '" + temp + "' failed (disk full?)");
  });
}

}  // namespace dlo
