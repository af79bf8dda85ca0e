#include "dlo/mrpt/rawlog_scan_source.h"

#include <mrpt/maps/registerAllClasses.h>
#include <mrpt/obs/CAction.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/rtti/CObject.h>
#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "dlo/files/error.h"
#include "dlo/mrpt/observation_to_scan.h"

namespace dlo {

namespace {

/// How MRPT 2.5 serializes an object: a length byte with the high bit set, the class name, a
/// version byte, the fields, and this end flag.
constexpr uint8_t kSerializationEndFlag = 0x88;

/// The bytes an mrpt::obs::CActionCollection entry starts with (length byte and class name).
const std::string& actionCollectionHeader() {
  static const std::string header = [] {
    const std::string name = "mrpt::obs::CActionCollection";
    return std::string(1, static_cast<char>(0x80 | name.size())) + name;
  }();
  return header;
}

bool hasGzipMagic(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  unsigned char magic[2] = {0, 0};
  f.read(reinterpret_cast<char*>(magic), 2);
  return f.gcount() == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
}

/// Whether the (decompressed) file starts like a serialized MRPT object: a length byte with the
/// high bit set, then the name of a registered class. Tells a rawlog whose first entry is
/// truncated (corrupt, keep going) from a file that is not a rawlog at all (input error).
bool startsWithMrptObjectHeader(const std::string& path) {
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) return false;
  uint8_t length = 0;
  if (in.Read(&length, 1) != 1 || (length & 0x80) == 0) return false;
  std::string name(length & 0x7f, '\0');
  if (name.empty() || in.Read(name.data(), name.size()) != name.size()) return false;
  return mrpt::rtti::findRegisteredClass(name) != nullptr;
}

}  // namespace

RawlogScanSource::RawlogScanSource(const std::string& path, const ScanSourceOptions& options)
    : path_(path), options_(options) {
  // A static library's registration code is only linked when referenced: make sure every class
  // a rawlog may hold can be deserialized (else it would read as "corrupt").
  mrpt::obs::registerAllClasses_mrpt_obs();
  mrpt::maps::registerAllClasses_mrpt_maps();
  if (!std::ifstream(path, std::ios::binary)) {
    throw InputError("cannot open rawlog '" + path + "': no such file or not readable.");
  }
  gzipped_ = hasGzipMagic(path);
  if (!in_.open(path)) throw InputError("cannot open rawlog '" + path + "'.");
  archive_ = mrpt::serialization::archiveUniquePtrFrom(input_);
  if (!readEntry() && !stats_.error.empty() && !startsWithMrptObjectHeader(path)) {
    throw InputError("'" + path +
                     "' is not an MRPT rawlog: it does not start with a serialized MRPT object.");
  }
}

size_t RawlogScanSource::PeekableInput::Read(void* buffer, size_t count) {
  char* out = static_cast<char*>(buffer);
  size_t served = 0;
  while (served < count) {
    if (buffered() == 0) {
      // A large read goes straight to the stream, a small one refills the buffer.
      if (count - served >= kChunk) return served + in_.Read(out + served, count - served);
      fill(kChunk);
      if (buffered() == 0) break;  // the end of the stream
    }
    const size_t n = std::min(count - served, buffered());
    std::copy_n(buffer_.data() + begin_, n, out + served);
    begin_ += n;
    served += n;
  }
  return served;
}

void RawlogScanSource::PeekableInput::fill(size_t want) {
  const size_t kept = buffered();
  if (kept >= want) return;
  if (buffer_.size() < want) buffer_.resize(want);
  std::copy(buffer_.begin() + static_cast<std::ptrdiff_t>(begin_),
            buffer_.begin() + static_cast<std::ptrdiff_t>(end_), buffer_.begin());
  begin_ = 0;
  end_ = kept;
  // A short read is the end of the stream (or an error, which the next read meets again).
  end_ += in_.Read(buffer_.data() + end_, want - kept);
}

std::string_view RawlogScanSource::PeekableInput::peek(size_t count) {
  fill(count);
  return std::string_view(buffer_.data() + begin_, std::min(count, buffered()));
}

mrpt::serialization::CSerializable::Ptr RawlogScanSource::readActionCollection() {
  auto fail = [](const std::string& why) {
    throw std::runtime_error("an action collection " + why);
  };
  std::string header(actionCollectionHeader().size(), '\0');
  input_.Read(header.data(), header.size());  // what readEntry() peeked at
  uint8_t version = 0;
  uint32_t count = 0;
  *archive_ >> version >> count;
  if (version != 0) fail("has version " + std::to_string(version) + " (0 expected)");
  for (uint32_t i = 0; i < count; ++i) {
    const mrpt::serialization::CSerializable::Ptr element = archive_->ReadObject();
    if (!std::dynamic_pointer_cast<mrpt::obs::CAction>(element)) {
      fail("holds " + (element ? shortClassName(*element) : std::string("a null object")) +
           " where action " + std::to_string(i) + " belongs");
    }
  }
  uint8_t end = 0;
  *archive_ >> end;
  if (end != kSerializationEndFlag) fail("does not end with MRPT's end-of-object flag");
  return std::make_shared<mrpt::obs::CActionCollection>();
}

bool RawlogScanSource::readEntry() {
  object_.reset();
  if (finished_) return false;
  const uint64_t start = input_.position();
  try {
    const bool actions = input_.peek(actionCollectionHeader().size()) == actionCollectionHeader();
    object_ = actions ? readActionCollection() : archive_->ReadObject();
    object_index_ = stats_.entries_read++;
    return true;
  } catch (const std::exception& e) {
    finished_ = true;
    const uint64_t now = input_.position();
    // Nothing consumed and at the end: the file ended cleanly between two entries.
    if (now == start && input_.atEnd()) return false;
    const std::string offset =
        "byte offset " + std::to_string(start) + (gzipped_ ? " of the decompressed stream" : "");
    stats_.error = "rawlog '" + path_ + "' is corrupt at entry " +
                   std::to_string(stats_.entries_read) + " (" + offset + "): " +
                   (input_.atEnd() ? std::string("the file ends inside that entry (truncated)")
                                   : "it could not be read (" + oneLineMessage(e) + ")") +
                   "; the " + std::to_string(stats_.entries_read) + " entries before it were read.";
    return false;
  }
}

void RawlogScanSource::queueObservations() {
  if (!object_) return;
  if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object_)) {
    for (const auto& o : *sf) {
      if (o) pending_.push_back(o);
    }
  } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object_)) {
    pending_.push_back(o);
  } else if (!std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(object_)) {
    // Actions are part of the pair layout, not data to report; anything else is.
    ++stats_.skipped_by_class[shortClassName(*object_)];
  }
  object_.reset();
}

mrpt::obs::CObservation::Ptr RawlogScanSource::nextObservation() {
  for (;;) {
    if (!pending_.empty()) {
      auto o = pending_.front();
      pending_.pop_front();
      return o;
    }
    queueObservations();
    if (!pending_.empty()) continue;
    if (!readEntry()) return nullptr;
  }
}

bool RawlogScanSource::next(TimedScan& scan) {
  for (;;) {
    const auto obs = nextObservation();
    if (!obs) return false;
    scan.entry_index = object_index_;  // observations of a sensory frame share its entry
    if (admitObservation(*obs, options_, scan, stats_)) {
      scan.observation = obs;
      return true;
    }
  }
}

}  // namespace dlo
