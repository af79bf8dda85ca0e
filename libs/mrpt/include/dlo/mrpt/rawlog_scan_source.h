/// \file rawlog_scan_source.h
/// \brief TimedScans from an MRPT rawlog, read one entry at a time.
#pragma once

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dlo/mrpt/scan_source.h"

namespace dlo {

/// Reads an MRPT `.rawlog` (plain or gzip) as a stream of TimedScans, never holding more than one
/// entry in memory, so rawlogs of millions of observations are fine. Both layouts are read:
/// (CActionCollection, CSensoryFrame) pairs, where each observation of a sensory frame becomes a
/// scan, and observation-only. Classes are handled as observationToTimedScan() says; all others
/// are skipped and counted by class name in stats().
///
/// A rawlog that breaks part way (truncated copy, corrupt bytes, a class this MRPT does not know)
/// is not an exception: next() returns false after the last readable entry and stats().error
/// names the entry index and byte offset, so the caller decides whether a partial input is fine.
///
///     dlo::RawlogScanSource source("drive.rawlog", options);
///     dlo::TimedScan scan;
///     while (source.next(scan)) odometry.add(scan);
///     if (!source.stats().error.empty()) warn(source.stats().error);
class RawlogScanSource : public ScanSource {
 public:
  /// Opens `path` and reads its first entry.
  /// \throws InputError naming the file if it is missing, unreadable, or its first entry is not
  ///         an MRPT serialized object (not a rawlog at all). An empty file is an empty rawlog.
  RawlogScanSource(const std::string& path, const ScanSourceOptions& options = {});

  bool next(TimedScan& scan) override;
  const ScanSourceStats& stats() const override { return stats_; }

  /// The next observation as stored (both layouts flattened), without conversion, label filter
  /// or counting of skipped classes: for tools that copy or inspect observations. Do not mix
  /// with next() on the same source. \return nullptr at the end or where the file broke.
  mrpt::obs::CObservation::Ptr nextObservation();

 private:
  /// The decompressed rawlog, buffered, with a look-ahead: readEntry() peeks at the class name
  /// of the next entry before MRPT deserializes it. MRPT reads some arrays one element per call
  /// (a Velodyne sweep's per-point timestamps: some 130k reads of 8 bytes), and each would
  /// otherwise be a call into zlib (docs/benchmarks.md).
  class PeekableInput {
   public:
    explicit PeekableInput(mrpt::io::CFileGZInputStream& in) : in_(in) {}
    /// CArchiveStreamBase's interface: buffered bytes are served first.
    size_t Read(void* buffer, size_t count);
    size_t Write(const void*, size_t) { return 0; }
    std::string getStreamDescription() const { return in_.getStreamDescription(); }
    /// The next `count` bytes (fewer at the end of the file), left to be read again; valid until
    /// the next call.
    std::string_view peek(size_t count);
    /// Decompressed bytes consumed so far.
    uint64_t position() { return in_.getPosition() - buffered(); }
    bool atEnd() { return buffered() == 0 && in_.checkEOF(); }

   private:
    /// Reads of at least this many bytes bypass the buffer; smaller ones refill it this much.
    static constexpr size_t kChunk = 64 * 1024;
    size_t buffered() const { return end_ - begin_; }
    /// Moves the buffered bytes to the front and reads more after them, up to `want` in all
    /// (fewer at the end of the file).
    void fill(size_t want);

    mrpt::io::CFileGZInputStream& in_;
    std::vector<char> buffer_;
    size_t begin_ = 0;  ///< first unread byte of buffer_
    size_t end_ = 0;    ///< one past the last byte read into buffer_
  };

  /// Reads the next serialized object into `object_`. \return false at the end or on error.
  bool readEntry();
  /// Reads an mrpt::obs::CActionCollection entry without MRPT's CActionCollection::serializeFrom,
  /// which dereferences a null pointer when an element is not an action (found by fuzzing).
  /// The actions are read and checked, then dropped: scans do not use them.
  mrpt::serialization::CSerializable::Ptr readActionCollection();
  /// Queues the observations of the entry just read (none for an action or unknown object).
  void queueObservations();

  std::string path_;
  ScanSourceOptions options_;
  bool gzipped_ = false;
  mrpt::io::CFileGZInputStream in_;
  PeekableInput input_{in_};
  std::unique_ptr<mrpt::serialization::CArchive> archive_;
  mrpt::serialization::CSerializable::Ptr object_;
  size_t object_index_ = 0;  ///< Entry index of object_.
  std::deque<mrpt::obs::CObservation::Ptr> pending_;
  bool finished_ = false;
  ScanSourceStats stats_;
};

}  // namespace dlo
