/// \file atomic_file.h
/// \brief ExportError and all-or-nothing file writing through a temporary file.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dlo {

/// An export that could not be written. what() is one sentence naming the file and the reason.
class ExportError : public std::runtime_error {
 public:
  explicit ExportError(const std::string& message) : std::runtime_error(message) {}
};

/// Calls `write(temp)` with temp = `path` + ".tmp" (same folder, hence same file system) and
/// renames temp to `path` on success, so readers never see a half-written export and a failed
/// export leaves the previous file untouched. On any exception from `write` or a failed rename,
/// the temporary file is removed and an ExportError naming `path` is thrown (the cause is kept to
/// its first line: MRPT exceptions carry a stack trace).
void writeAtomically(const std::string& path,
                     const std::function<void(const std::string& temp)>& write);

/// Writes `bytes` to `path` atomically (see writeAtomically()).
void writeBytesAtomically(const std::string& path, const std::vector<unsigned char>& bytes);

}  // namespace dlo
