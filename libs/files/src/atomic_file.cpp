#include "dlo/files/atomic_file.h"

#include <filesystem>
#include <fstream>

namespace dlo {

namespace fs = std::filesystem;

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
  const std::string temp = path + ".tmp";
  std::error_code ec;
  try {
    write(temp);
  } catch (const std::exception& e) {
    fs::remove(temp, ec);
    throw OutputError("cannot write '" + path + "' (" + firstLine(e.what()) + ").");
  }
  if (!fs::is_regular_file(temp, ec)) {
    throw OutputError("cannot write '" + path + "' (the writer produced no file).");
  }
  fs::rename(temp, path, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw OutputError("cannot write '" + path +
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

AtomicOutput::AtomicOutput(const std::string& path) : path_(path), temp_(path + ".tmp") {
  std::error_code ec;
  fs::remove_all(temp_, ec);
}

AtomicOutput::~AtomicOutput() {
  if (committed_) return;
  std::error_code ec;
  if (keep_partial_ && fs::exists(temp_, ec)) {
    fs::remove_all(partialPath(), ec);
    fs::rename(temp_, partialPath(), ec);
  } else {
    fs::remove_all(temp_, ec);
  }
}

void AtomicOutput::commit() {
  std::error_code ec;
  fs::rename(temp_, path_, ec);  // POSIX: a folder replaces an empty folder, a file a file
  if (ec) {
    throw OutputError("cannot rename '" + temp_ + "' to '" + path_ + "': " + ec.message() + ".");
  }
  committed_ = true;
}

}  // namespace dlo
