/// \file atomic_file.h
/// \brief All-or-nothing outputs: written under a temporary name beside the final one and
/// renamed at the end, so that readers never see a half-written file or folder and a failed
/// write leaves the previous output untouched. The one such writer of DLO.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "dlo/files/error.h"

namespace dlo {

/// Calls `write(temp)` with temp = `path` + ".tmp" (same folder, hence same file system) and
/// renames temp to `path` on success. On any exception from `write` or a failed rename, the
/// temporary file is removed and an OutputError naming `path` is thrown: "cannot write 'path'
/// (cause)." with the cause kept to its first line (MRPT exceptions carry a stack trace).
void writeAtomically(const std::string& path,
                     const std::function<void(const std::string& temp)>& write);

/// Writes `bytes` to `path` atomically (see writeAtomically()).
void writeBytesAtomically(const std::string& path, const std::vector<unsigned char>& bytes);

/// An output (a file or a folder) filled over a long run, such as a rawlog written scan by scan:
/// the owner writes to temp() and calls commit() at the end, which renames temp() to path().
/// Destroyed without commit() (an error part way), it keeps what was written as partialPath()
/// when setKeepPartial(true) was called, and removes it otherwise.
class AtomicOutput {
 public:
  /// Removes a temp() left by a run that was killed. Creates nothing: the owner does.
  explicit AtomicOutput(const std::string& path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// The final name.
  const std::string& path() const { return path_; }
  /// Where the output is written until commit(): path() + ".tmp".
  const std::string& temp() const { return temp_; }
  /// Where an output abandoned with setKeepPartial(true) is kept: path() + ".partial".
  std::string partialPath() const { return path_ + ".partial"; }

  /// Whether an output abandoned without commit() is worth keeping as partialPath().
  void setKeepPartial(bool keep) { keep_partial_ = keep; }

  /// Renames temp() to path() (an empty folder at path() is replaced). The owner has closed
  /// what it wrote. \throws OutputError "cannot rename 'temp' to 'path': reason."
  void commit();

 private:
  std::string path_;
  std::string temp_;
  bool keep_partial_ = false;
  bool committed_ = false;
};

}  // namespace dlo
