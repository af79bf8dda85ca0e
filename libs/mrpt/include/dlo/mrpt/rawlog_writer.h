/// \file rawlog_writer.h
/// \brief Writing an MRPT rawlog safely: to a temporary file, renamed at the end.
#pragma once

#include <mrpt/io/CStream.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>
#include <memory>
#include <string>

#include "dlo/files/atomic_file.h"

namespace dlo {

/// Streams entries into `path`: observations (the observation-only layout), or actions and sensory
/// frames in turn (the (CActionCollection, CSensoryFrame) layout); gzip-compressed if the name
/// ends in `.gz`. They go to `path + ".tmp"` first and commit() renames it, so an existing `path`
/// is never replaced by a half-written file. If the writer is destroyed without commit() (an error
/// part way), whatever was written is kept as `path + ".partial"` rather than lost.
class RawlogWriter {
 public:
  /// \throws OutputError naming the file if the temporary file cannot be created.
  explicit RawlogWriter(const std::string& path);
  ~RawlogWriter();
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  /// Appends one entry: an observation, an action collection or a sensory frame.
  void write(const mrpt::serialization::CSerializable& entry);

  /// Entries written so far.
  size_t count() const { return count_; }

  /// Closes the file and renames it to the final path. \throws OutputError if renaming fails.
  void commit();

  /// Where the entries written so far are kept if commit() is never called.
  std::string partialPath() const { return output_.partialPath(); }

 private:
  AtomicOutput output_;  ///< declared first: destroyed after the stream is closed
  std::unique_ptr<mrpt::io::CStream> out_;
  std::unique_ptr<mrpt::serialization::CArchive> archive_;
  size_t count_ = 0;
};

}  // namespace dlo
